// The drill's sound played live through OpenAL Soft: frames pushed by the producer cross a
// lock-free ring to an audio thread of the player's own, which renders them (DrillSound) into a
// queue of streaming buffers. Without an audio device the player still takes frames (and counts
// them) but plays nothing: it never fails its caller.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "osteon/audio/drill_sound.h"

namespace osteon::audio {

class SoundPlayer {
 public:
  // Opens the default device and starts the audio thread; when none opens, deviceError() says
  // why and nothing plays.
  SoundPlayer();
  ~SoundPlayer();
  SoundPlayer(const SoundPlayer&) = delete;
  SoundPlayer& operator=(const SoundPlayer&) = delete;

  bool device() const;
  const std::string& deviceError() const;
  // Producer thread only: never waits, locks or allocates; a full ring drops (counted).
  void push(const SoundFrame& frame) noexcept;
  // Any thread: the sound glides to silence, or back.
  void setMuted(bool muted) noexcept;
  bool muted() const noexcept;
  std::uint64_t frames() const noexcept;   // frames pushed
  std::uint64_t dropped() const noexcept;  // frames the ring refused

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace osteon::audio
