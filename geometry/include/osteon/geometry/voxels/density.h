// The seed's drilling difficulty d (section 3.5) per voxel, initialised by a rule: cortical
// bone within a shell under the surface, cancellous bone deeper inside.
#pragma once

#include <cstdint>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

class EmbreeScene;

struct DensityRule {
  double corticalThicknessMm = 2.0;  // voxel centres this close to the surface are cortical
  Density corticalDensity = 40;      // drilling steps to remove a cortical voxel
  Density cancellousDensity = 15;    // drilling steps to remove a cancellous voxel
};

struct DensityStats {
  std::uint64_t corticalVoxels = 0;
  std::uint64_t cancellousVoxels = 0;
  std::uint64_t distanceQueries = 0;  // per-voxel surface distance look-ups made
};

// Throws InputError when the rule has a negative thickness or non-positive densities.
void validateDensityRule(const DensityRule& rule);

// Sets density on every voxel with fill > 0 (0 elsewhere) from its centre's Euclidean
// distance to the mesh surface. Bricks farther than the shell from the surface are decided
// by one query at their centre. Parallel over bricks.
DensityStats assignDensity(VoxelGrid& grid, const EmbreeScene& surface, const DensityRule& rule);

}  // namespace osteon::geometry
