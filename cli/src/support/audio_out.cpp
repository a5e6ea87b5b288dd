#include "support/audio_out.h"

#include <algorithm>
#include <cctype>

#include "osteon/core/error.h"
#include "osteon/simulation/cutting.h"

namespace osteon::cli {

namespace sim = osteon::simulation;

namespace {

bool endsWithWav(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == ".wav";
}

// The WAV's errors name the temporary file it writes; the user knows the path they gave.
[[noreturn]] void rethrowNaming(const InputError& e, const std::string& temp,
                                const std::string& path) {
  const std::string what = e.what();
  if (what.compare(0, temp.size(), temp) == 0) throw InputError(path + what.substr(temp.size()));
  throw e;
}

}  // namespace

AudioOut::AudioOut(const std::string& path, const std::vector<std::string>& inputs) {
  if (path.empty()) return;
  if (!endsWithWav(path)) {
    throw InputError(path + ": --audio-out writes a 16-bit PCM .wav file (give it a .wav name)");
  }
  geometry::refuseOverwritingInputs({path}, inputs);
  file_.emplace(path);
  try {
    wav_.emplace(file_->tempPath());
  } catch (const InputError& e) {
    rethrowNaming(e, file_->tempPath(), path);
  }
}

void AudioOut::follow(sim::ForceLogWriter& forces) {
  if (wav_) forces.tapRows(this);
}

void AudioOut::row(const sim::ForceLogRow& r) noexcept {
  // The removal rate from the bone removed so far, row to row; the drill turns all run long
  // (the rows carry no switch), at the run's rpm (the default one where a row has none).
  const double dtS = r.tS - lastTS_;
  const double removal = dtS > 0.0 ? (r.removedMm3 - lastRemovedMm3_) / dtS : 0.0;
  lastTS_ = r.tS;
  lastRemovedMm3_ = r.removedMm3;
  const double rpm = r.rpm > 0.0 ? r.rpm : sim::DrillSettings{}.rpm;
  wav_->add({r.tS, rpm, std::max(0.0, removal), r.magnitudeN, true});
}

void AudioOut::commit() {
  if (!wav_) return;
  try {
    wav_->finish();
  } catch (const InputError& e) {
    rethrowNaming(e, file_->tempPath(), file_->path());
  }
  file_->commit();
}

}  // namespace osteon::cli
