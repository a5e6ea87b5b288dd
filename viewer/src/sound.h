// The drill's sound in the viewer (docs/feel.md, "Sound"): fed each frame from the live
// runtime's display state (the removal rate from the bone removed between frames, the contact
// force, the drill switch), played through OpenAL Soft on the player's own thread. Without an
// audio device the viewer runs silent and says so once on stderr.
#pragma once

#include "osteon/audio/player.h"
#include "osteon/simulation/live.h"
#include "report.h"

namespace osteon::viewer {

class ViewerSound {
 public:
  explicit ViewerSound(bool muted);
  // A frame's display state; nothing when the simulation has not stepped since the last one.
  void feed(const simulation::DisplayState& display) noexcept;
  void toggleMute() noexcept { player_.setMuted(!player_.muted()); }
  // The report's "sound" object: device, muted, frames, dropped.
  void report(ViewerReport& report) const;

 private:
  audio::SoundPlayer player_;
  double lastTS_ = -1.0;
  double lastRemovedMm3_ = 0.0;
};

}  // namespace osteon::viewer
