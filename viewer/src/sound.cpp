#include "sound.h"

#include <algorithm>
#include <cstdio>

#include "osteon/simulation/cutting.h"

namespace osteon::viewer {

ViewerSound::ViewerSound(bool muted) {
  player_.setMuted(muted);
  if (!player_.device()) {
    std::fprintf(stderr, "osteon-viewer: %s; running without sound\n",
                 player_.deviceError().c_str());
  }
}

void ViewerSound::feed(const simulation::DisplayState& d) noexcept {
  if (d.tS < 0.0) return;
  if (d.tS < lastTS_) {  // a bone loaded again or another opened: its own clock and removal
    lastTS_ = -1.0;
    lastRemovedMm3_ = 0.0;
  }
  if (d.tS == lastTS_) return;
  const double dtS = lastTS_ < 0.0 ? d.tS : d.tS - lastTS_;
  const double removal = dtS > 0.0 ? (d.removedVolumeMm3 - lastRemovedMm3_) / dtS : 0.0;
  lastTS_ = d.tS;
  lastRemovedMm3_ = d.removedVolumeMm3;
  // The default drill speed until the viewer sets one (simulation/cutting.h).
  player_.push({d.tS, d.settings.rpm, std::max(0.0, removal), d.contact.magnitudeN, d.drillOn});
}

void ViewerSound::report(ViewerReport& r) const {
  r.soundDevice = player_.device();
  r.soundMuted = player_.muted();
  r.soundFrames = player_.frames();
  r.soundDropped = player_.dropped();
}

}  // namespace osteon::viewer
