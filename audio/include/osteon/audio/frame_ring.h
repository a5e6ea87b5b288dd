// The frames of the drill's sound on their way from the producer (the run's row stream on the
// logging thread, or the viewer's render loop) to the audio thread: core's lock-free ring, with
// what it refused counted. The producer never waits, locks or allocates.
#pragma once

#include <atomic>
#include <cstdint>

#include "osteon/audio/drill_sound.h"
#include "osteon/core/handoff.h"

namespace osteon::audio {

class FrameRing {
 public:
  // 1024 frames: a second of 1 kHz rows, far more than the audio thread lets pile up.
  static constexpr std::size_t kCapacity = 1024;

  // Producer thread only. False, and counted as dropped, when the ring is full.
  bool push(const SoundFrame& frame) noexcept {
    pushed_.fetch_add(1, std::memory_order_relaxed);
    if (ring_.push(frame)) return true;
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  // Consumer thread only. False when empty.
  bool pop(SoundFrame& frame) noexcept { return ring_.pop(frame); }

  std::uint64_t frames() const noexcept { return pushed_.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  core::SpscRing<SoundFrame, kCapacity> ring_;
  std::atomic<std::uint64_t> pushed_{0};
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace osteon::audio
