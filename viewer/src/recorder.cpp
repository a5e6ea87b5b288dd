#include "recorder.h"

#include <charconv>
#include <cmath>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"

namespace osteon::viewer {

namespace {

// Shortest text that reads back as the same double.
void appendNumber(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace

bool PathRecorder::start() {
  const int s = state_.load(std::memory_order_acquire);
  if (s != kIdle) return false;
  if (samples_.size() != capacity_) samples_.resize(capacity_);
  count_.store(0, std::memory_order_relaxed);
  overflowed_.store(false, std::memory_order_relaxed);
  state_.store(kRecording, std::memory_order_release);
  return true;
}

void PathRecorder::requestStop() {
  int expected = kRecording;
  state_.compare_exchange_strong(expected, kStopRequested, std::memory_order_acq_rel);
}

void PathRecorder::add(double tS, const simulation::ToolPose& pose, bool drillOn) noexcept {
  const int s = state_.load(std::memory_order_acquire);
  if (s == kStopRequested) {
    state_.store(kFinished, std::memory_order_release);
    return;
  }
  if (s != kRecording) return;
  const std::size_t n = count_.load(std::memory_order_relaxed);
  if (n >= samples_.size()) {
    overflowed_.store(true, std::memory_order_relaxed);
    state_.store(kFinished, std::memory_order_release);
    return;
  }
  samples_[n] = RecordedSample{tS, pose.tipMm, pose.orientation, drillOn};
  count_.store(n + 1, std::memory_order_release);
}

std::string PathRecorder::csv(double periodS) const {
  const std::size_t n = sampleCount();
  std::string out = "t,x,y,z,drill_on,qw,qx,qy,qz\n";
  out.reserve(out.size() + n * 160);
  if (n == 0) return out;
  const long long k0 = std::llround(samples_[0].tS / periodS);
  long long previous = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const RecordedSample& s = samples_[i];
    // Whole periods since the first sample, as a fixed-step replay computes its times.
    const long long k = std::llround(s.tS / periodS) - k0;
    if (k <= previous) continue;  // times must increase (never happens with a steady loop)
    previous = k;
    const bool on = (i + 1 < n ? samples_[i + 1] : s).drillOn;
    appendNumber(out, double(k) * periodS);
    for (const double v : {s.tipMm.x, s.tipMm.y, s.tipMm.z}) {
      out += ',';
      appendNumber(out, v);
    }
    out += on ? ",1" : ",0";
    for (const double v : {s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z}) {
      out += ',';
      appendNumber(out, v);
    }
    out += '\n';
  }
  return out;
}

void PathRecorder::write(const std::string& path, double periodS) {
  const std::size_t n = sampleCount();
  if (n < 2) {
    discard();
    throw InputError(path + ": the recording holds " + std::to_string(n) +
                     " sample(s); a path needs at least two (nothing written)");
  }
  const std::string text = csv(periodS);
  discard();
  geometry::writeFileAtomically(path, text);
}

void PathRecorder::discard() {
  count_.store(0, std::memory_order_relaxed);
  state_.store(kIdle, std::memory_order_release);
}

}  // namespace osteon::viewer
