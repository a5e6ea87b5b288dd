// Motions a hand makes with a tool, as drill paths from a portal plan (path.h): what the
// benchmarks and tests drive the step with beyond the seed's straight portal paths. (A tilted
// portal path is PortalPathOptions::tiltDeg.)
#pragma once

#include "osteon/simulation/path.h"

namespace osteon::simulation {

struct LateralSweepOptions {
  double durationS = 7.0;
  double amplitudeMm = 2.5;     // side to side, across the plane of travel and the normal
  double frequencyHz = 0.5;
  double reachS = 1.0;          // from clear of the surface down to startDepthMm
  double startDepthMm = 1.0;    // the tip's centre below the surface's tangent plane
  double sinkMmPerS = 0.3;      // then deeper at this rate, so every pass meets bone
  double sampleS = 0.005;       // waypoint spacing
};

// The tool held at the plan's orientation, its tip shaving the surface at the portal's entry:
// down to startDepthMm in reachS, then swept sinusoidally side to side while it sinks. The
// drill is on throughout.
DrillPath lateralSweepPath(const PortalPlan& plan, const LateralSweepOptions& options = {});

struct FastPushOptions {
  double durationS = 7.0;
  double holdS = 0.5;      // at the plan's start, clear of the surface
  double pushS = 0.1;      // then to depthMm past the entry in this long
  double depthMm = 6.0;
  bool drillOn = true;
};

// The tool pushed fast along the plan's direction into the bone and held there.
DrillPath fastPushPath(const PortalPlan& plan, const FastPushOptions& options = {});

}  // namespace osteon::simulation
