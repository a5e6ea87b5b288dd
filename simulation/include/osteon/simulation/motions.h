// Motions a hand makes with a tool, as drill paths from a portal plan (path.h): what the
// benchmarks and tests drive the step with beyond the seed's straight portal paths. (A tilted
// portal path is PortalPathOptions::tiltDeg.)
#pragma once

#include "osteon/simulation/path.h"

namespace osteon::simulation {

struct LateralSweepOptions {
  double durationS = 7.0;
  double amplitudeMm = 2.5;  // side to side, across the plane of travel and the normal
  double frequencyHz = 0.5;
  double reachS = 1.0;        // from clear of the surface down to startDepthMm
  double startDepthMm = 1.0;  // the tip's centre below the surface's tangent plane
  double sinkMmPerS = 0.3;    // then deeper at this rate, so every pass meets bone
  double sampleS = 0.005;     // waypoint spacing
};

// The tool held at the plan's orientation, its tip shaving the surface at the portal's entry:
// down to startDepthMm in reachS, then swept sinusoidally side to side while it sinks. The
// drill is on throughout.
DrillPath lateralSweepPath(const PortalPlan& plan, const LateralSweepOptions& options = {});

struct FastPushOptions {
  double durationS = 7.0;
  double holdS = 0.5;  // at the plan's start, clear of the surface
  double pushS = 0.1;  // then to depthMm past the entry in this long
  double depthMm = 6.0;
  bool drillOn = true;
};

// The tool pushed fast along the plan's direction into the bone and held there.
DrillPath fastPushPath(const PortalPlan& plan, const FastPushOptions& options = {});

struct IntactPushOptions {
  double outsideMm = 6.0;  // the tip's centre starts this far outside the entry point
  double depthMm = 10.0;   // and is pushed to this far past it (the entry is on the surface)
  double pushS = 1.0;      // at constant speed over this long, then held
  double drillOnS = 5.0;   // the drill off until here, then on
  double durationS = 7.0;
};

// A push into intact bone with the drill off, then on: the tool pointing along the inward
// normal at the portal's entry, pushed from outsideMm outside to depthMm past the surface and
// held; the drill turns on at drillOnS (off at that instant, on from the next step). Under
// proxy coupling the bone stops the tool until the drill cuts its way in from the surface.
DrillPath intactPushPath(const PortalPlan& plan, const IntactPushOptions& options = {});

struct TremorOptions {
  // Per axis, the sines' amplitudes sum to these: at most amplitudeMm along each of the three
  // axes, and at most amplitudeDeg about each of the two axes across the shaft (about the tip).
  double amplitudeMm = 0.3;
  double amplitudeDeg = 3.0;
  // 1-9 Hz, the lower the larger (a hand's drift under its physiological tremor).
  double frequenciesHz[4] = {1.0, 3.0, 5.5, 9.0};
  double weights[4] = {0.4, 0.3, 0.2, 0.1};  // of the amplitudes; sum to 1
  unsigned seed = 31;                        // the phases (std::mt19937's raw output)
  double sampleS = 0.002;                    // waypoint spacing
};

// A hand's path: `base` (e.g. a portal path) with a tremor of sines on top, its tip displaced
// and the tool turned about its tip; the drill as `base` has it. The same seed gives the same
// path bit for bit.
DrillPath tremorPath(const DrillPath& base, const TremorOptions& options = {});

}  // namespace osteon::simulation
