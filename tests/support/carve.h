// A slow, obviously correct material removal through the refined voxels' sample-mutation
// interface: the reference osteon::simulation::MaterialRemoval is held against, and the way
// geometry's tests drill without depending on simulation.
#pragma once

#include <cstdint>

#include "osteon/geometry/hierarchy/refinement.h"

namespace osteon::test {

// The points within radiusMm of the segment a-b (a sphere when a == b); sideOnly: without
// end caps.
struct Cut {
  glm::dvec3 aMm{0.0}, bMm{0.0};
  double radiusMm = 0.0;
  bool sideOnly = false;
  bool contains(const glm::dvec3& pMm) const;
};

struct Carved {
  std::uint64_t removedFill = 0;
  std::uint64_t samplesRemoved = 0;
  std::uint64_t samplesDecremented = 0;
  std::uint64_t voxelsEmptied = 0;
};

// Every sample with bone whose centre the cut contains loses `decrement` density; at 0 it is
// removed. Visits every voxel near the cut (no hierarchy query, no shortcut).
Carved carve(geometry::RefinedVoxels& voxels, const Cut& cut, int decrement = 1);
inline Carved carveSphere(geometry::RefinedVoxels& voxels, const glm::dvec3& centreMm,
                          double radiusMm, int decrement = 1) {
  return carve(voxels, Cut{centreMm, centreMm, radiusMm, false}, decrement);
}

}  // namespace osteon::test
