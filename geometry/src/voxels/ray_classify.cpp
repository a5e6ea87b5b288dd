#include "ray_classify.h"

#include <algorithm>
#include <cmath>

namespace osteon::geometry::detail {

void pairByParity(const std::vector<RayHit>& hits, std::vector<Interval>& intervals) {
  intervals.clear();
  for (std::size_t i = 0; i + 1 < hits.size(); i += 2)
    intervals.push_back({hits[i].t, hits[i + 1].t});
}

RayOutcome classifyRay(std::vector<RayHit>& hits, int outwardSign, double toleranceMm,
                       std::vector<Interval>& intervals) {
  intervals.clear();
  std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; });

  // Merge clusters of hits at (nearly) one place along the ray.
  std::size_t out = 0;
  for (std::size_t i = 0; i < hits.size();) {
    const double tol = toleranceMm + 1e-6 * std::abs(hits[i].t);
    std::size_t j = i;
    int net = 0;  // oriented: entries minus exits
    while (j < hits.size() && hits[j].t - hits[i].t <= tol) {
      // facing * outwardSign < 0: the ray enters the solid.
      net += hits[j].facing * outwardSign < 0 ? 1 : (hits[j].facing * outwardSign > 0 ? -1 : 0);
      ++j;
    }
    if (outwardSign == 0) {
      hits[out++] = hits[i];  // unoriented: one crossing per cluster
    } else if (net != 0) {
      hits[out++] = {hits[i].t, net > 0 ? -outwardSign : outwardSign};
    }
    i = j;
  }
  hits.resize(out);

  if (outwardSign == 0) {
    if (hits.size() % 2 != 0) return RayOutcome::Unresolved;
    pairByParity(hits, intervals);
    return RayOutcome::Parity;
  }

  // Oriented: alternating in/out is plain parity; otherwise a valid winding walk (never
  // negative, back to zero at the end) still classifies overlapping closed shells correctly.
  bool alternating = hits.size() % 2 == 0;
  int winding = 0;
  bool windingValid = true;
  double openedAt = 0.0;
  for (std::size_t i = 0; i < hits.size(); ++i) {
    const bool enters = hits[i].facing * outwardSign < 0;
    if (enters != (i % 2 == 0)) alternating = false;
    if (enters) {
      if (winding++ == 0) openedAt = hits[i].t;
    } else {
      if (--winding < 0) {
        windingValid = false;
        break;
      }
      if (winding == 0) intervals.push_back({openedAt, hits[i].t});
    }
  }
  if (!windingValid || winding != 0) {
    intervals.clear();
    return RayOutcome::Unresolved;
  }
  return alternating ? RayOutcome::Parity : RayOutcome::Winding;
}

}  // namespace osteon::geometry::detail
