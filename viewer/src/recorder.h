// Recording the tool's path at 1 kHz, as the haptic loop sampled it, to a CSV in the format
// `osteon drill --path` reads (t,x,y,z,drill_on,qw,qx,qy,qz), so a session drilled by hand
// replays with the same poses.
//
// The haptic thread appends to a buffer allocated when recording starts (no allocation, lock or
// throw in the loop); the render thread starts and stops it. Stopping is a hand-shake: the
// render thread asks, the haptic thread acknowledges at its next sample and writes no more, and
// only then is the buffer read (or at once when the loops have been joined).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "osteon/simulation/tool.h"

namespace osteon::viewer {

struct RecordedSample {
  double tS = 0.0;  // the haptic loop's time
  glm::dvec3 tipMm{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
  bool drillOn = false;
};

class PathRecorder {
 public:
  // Ten minutes at 1 kHz (72 bytes a sample, 43 MB, allocated on start); recording stops by
  // itself when full.
  static constexpr std::size_t kDefaultCapacity = 600000;
  explicit PathRecorder(std::size_t capacity = kDefaultCapacity) : capacity_(capacity) {}

  // ---- render thread ----
  // Arms the recorder: samples are kept from the haptic loop's next sample on. Allocates.
  // False when it is recording already or the previous recording was not taken yet.
  bool start();
  // Asks the haptic loop to stop recording; finished() turns true once it has.
  void requestStop();
  // The haptic loop will write no more (it acknowledged a stop, or the buffer filled). Call
  // forceFinished() instead once the loops have been joined.
  bool finished() const { return state_.load(std::memory_order_acquire) == kFinished; }
  void forceFinished() {
    if (recording()) state_.store(kFinished, std::memory_order_release);
  }
  bool recording() const {
    const int s = state_.load(std::memory_order_acquire);
    return s == kRecording || s == kStopRequested;
  }
  bool overflowed() const { return overflowed_.load(std::memory_order_relaxed); }
  std::size_t sampleCount() const { return count_.load(std::memory_order_acquire); }
  // Once finished(): the CSV. Times start at 0 on the first sample, in whole periods
  // (periodS) of the haptic loop so that a fixed-step replay samples exactly these poses.
  // drill_on on a row is the state over the segment that starts at it (as loadPathCsv reads
  // a path), so row k carries the state sampled at row k + 1's time.
  std::string csv(double periodS) const;
  // Writes csv() through an OutputFile (complete or not at all) and makes the recorder idle.
  // Throws InputError naming the file. Fewer than two samples is an InputError too: a path
  // needs two rows.
  void write(const std::string& path, double periodS);
  void discard();  // idle again without writing

  // ---- haptic thread ----
  void add(double tS, const simulation::ToolPose& pose, bool drillOn) noexcept;

 private:
  static constexpr int kIdle = 0, kRecording = 1, kStopRequested = 2, kFinished = 3;
  std::size_t capacity_;
  std::vector<RecordedSample> samples_;
  std::atomic<int> state_{kIdle};
  std::atomic<std::size_t> count_{0};
  std::atomic<bool> overflowed_{false};
};

}  // namespace osteon::viewer
