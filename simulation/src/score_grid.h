// The bone's fill between voxel centres, for plans and scores (exercise_plan.cpp, score.cpp).
#pragma once

#include <cmath>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::simulation {

// The fill fraction (0 empty, 1 full) at a point, trilinear between voxel centres.
inline double fillFractionAt(const geometry::VoxelGrid& grid, const glm::dvec3& pMm) {
  const glm::dvec3 g = grid.gridFromWorld(pMm) - 0.5;
  const glm::dvec3 base(std::floor(g.x), std::floor(g.y), std::floor(g.z));
  const glm::dvec3 f = g - base;
  const glm::ivec3 i0(base);
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c & 1) != 0, (c & 2) != 0, (c & 4) != 0);
    const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
    if (w > 0.0) sum += w * double(grid.fill(i0 + o));
  }
  return sum / double(geometry::kFillFull);
}

}  // namespace osteon::simulation
