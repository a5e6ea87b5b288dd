// The drill's sound as a 16-bit mono PCM WAV file (RIFF, 44-byte header), streamed as a run
// goes, and the offline rendering of a run's frames into one.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "osteon/audio/drill_sound.h"

namespace osteon::audio {

// The 44-byte header of a mono 16-bit PCM WAV holding `samples` samples.
std::array<std::uint8_t, 44> wavHeader(std::uint32_t sampleRateHz, std::uint32_t samples);

// Writes samples to `path` (the caller's temporary file: it puts it in place itself) through a
// fixed buffer; write() neither allocates nor throws. finish() writes the header's sizes and
// closes; it throws InputError naming the path if any write failed.
class WavWriter {
 public:
  WavWriter(const std::string& path, std::uint32_t sampleRateHz);  // InputError naming path
  ~WavWriter();
  WavWriter(const WavWriter&) = delete;
  WavWriter& operator=(const WavWriter&) = delete;

  void write(const float* samples, std::size_t n) noexcept;
  void finish();
  std::uint64_t samples() const { return samples_; }

 private:
  void flush() noexcept;

  std::string path_;
  std::uint32_t rateHz_;
  int fd_ = -1;
  int error_ = 0;  // errno of the first failed write
  std::uint64_t samples_ = 0;
  std::array<std::int16_t, 8192> buffer_{};
  std::size_t used_ = 0;
};

// A run's frames rendered into a WAV in the run's own time: each frame sets the synthesiser's
// target and the samples up to its time are rendered, so the same frames give the same bytes
// whatever the pace they came at.
class WavRecording {
 public:
  explicit WavRecording(const std::string& path);  // InputError naming path
  void add(const SoundFrame& frame) noexcept;
  void finish();  // InputError naming the path when the file could not be written
  std::uint64_t samples() const { return wav_.samples(); }

 private:
  DrillSound sound_;
  WavWriter wav_;
  std::uint64_t rendered_ = 0;
};

}  // namespace osteon::audio
