// Turning the raw hits of one ray into inside intervals (seed 3.2: inside by parity).
#pragma once

#include <vector>

namespace osteon::geometry::detail {

struct RayHit {
  double t;    // distance along the ray, mm
  int facing;  // sign of (geometric normal . ray direction); 0 for edge-on
};

struct Interval {
  double t0;
  double t1;
};

enum class RayOutcome {
  Parity,      // hits alternate in / out: parity and winding agree
  Winding,     // oriented mesh with overlapping shells: inside where winding > 0
  Unresolved,  // an odd or inconsistent hit list (a hole, or an edge Embree missed)
};

// Sorts and merges hits closer than toleranceMm (+ 1e-6 relative): one surface seen twice
// through a shared edge or vertex becomes one crossing, a graze of an oriented silhouette
// (in and out at once) becomes none. outwardSign is +1 for an outward-oriented mesh, -1 for
// an inward one, 0 when the mesh is not consistently oriented (parity only).
RayOutcome classifyRay(std::vector<RayHit>& hits, int outwardSign, double toleranceMm,
                       std::vector<Interval>& intervals);

// Pairs consecutive hits (after classifyRay merged them), dropping a last odd one.
void pairByParity(const std::vector<RayHit>& hits, std::vector<Interval>& intervals);

}  // namespace osteon::geometry::detail
