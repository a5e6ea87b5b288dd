// --audio-out FILE.wav (drill, drill --device, replay): the run's drill sound rendered offline
// from its rows as they are logged (docs/feel.md, "Sound"), in the run's own time, so the same
// run gives the same bytes. Written to a temporary file and put in place by commit(): a run
// that fails leaves no half file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "osteon/audio/wav_writer.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/force_log.h"

namespace osteon::cli {

class AudioOut : public simulation::RowTap {
 public:
  // Empty path: no sound. Otherwise refused before the run (InputError naming the path) unless
  // it ends in .wav, its folder is writable and it is none of `inputs`.
  AudioOut(const std::string& path, const std::vector<std::string>& inputs);

  // Taps `forces`' rows (nothing when off).
  void follow(simulation::ForceLogWriter& forces);
  void row(const simulation::ForceLogRow& row) noexcept override;
  // Finishes the file and puts it in place (with the run folder's set when inside it).
  void commit();

 private:
  std::optional<geometry::OutputFile> file_;
  std::optional<audio::WavRecording> wav_;  // after file_: closed before the temporary goes
  double lastTS_ = 0.0;
  double lastRemovedMm3_ = 0.0;
};

}  // namespace osteon::cli
