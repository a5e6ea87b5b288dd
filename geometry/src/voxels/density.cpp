#include "osteon/geometry/voxels/density.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/core/constants.h"

#include "osteon/core/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>

namespace osteon::geometry {

// Brick edge in voxels.
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

void validateDensityRule(const DensityRule& rule) {
  if (!std::isfinite(rule.corticalThicknessMm) || rule.corticalThicknessMm < 0.0) {
    std::ostringstream s;
    s << "--cortical-mm " << rule.corticalThicknessMm << ": must be a finite thickness >= 0";
    throw InputError(s.str());
  }
  if (rule.corticalDensity <= 0 || rule.cancellousDensity <= 0) {
    throw InputError("densities must be positive integers (cortical " +
                     std::to_string(rule.corticalDensity) + ", cancellous " +
                     std::to_string(rule.cancellousDensity) + ")");
  }
}

DensityStats assignDensity(VoxelGrid& grid, const EmbreeScene& surface, const DensityRule& rule) {
  validateDensityRule(rule);
  const glm::ivec3 dims = grid.dims();
  const double vs = grid.voxelSizeMm();
  const double shellMm = rule.corticalThicknessMm;
  // A brick whose centre is farther than this from the surface holds no cortical voxel.
  const double brickReachMm = shellMm + 0.5 * std::sqrt(3.0) * kBrickEdge * vs;
  // Voxel queries look a little past the shell so that a miss still bounds the next voxels.
  const double queryReachMm = shellMm + 2.0 * vs;
  std::atomic<std::uint64_t> corticalCount{0}, cancellousCount{0}, queryCount{0};

  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grid.brickCount()),
                    [&](const tbb::blocked_range<std::size_t>& range) {
    std::uint64_t nCortical = 0, nCancellous = 0, nQueries = 0;
    std::array<double, VoxelGrid::kBrickVoxels> lowerMm;
    std::array<double, VoxelGrid::kBrickVoxels> upperMm;
    for (std::size_t brick = range.begin(); brick != range.end(); ++brick) {
      const bool allocated = grid.brickAllocated(brick);
      const Fill uniformFill = grid.brickUniformFill(brick);
      if (!allocated && uniformFill == 0) continue;
      const glm::ivec3 lo = grid.brickCoord(brick) * kBrickEdge;
      const glm::ivec3 hi = glm::min(lo + kBrickEdge, dims);
      const glm::ivec3 span = hi - lo;
      const glm::dvec3 centre = grid.worldFromGrid(glm::dvec3(lo) + 0.5 * glm::dvec3(span));
      ++nQueries;
      if (surface.distanceWithin(centre, brickReachMm) < 0.0 && !allocated) {
        // Deep inside: the whole brick is cancellous and stays a few bytes.
        grid.setBrickUniform(brick, uniformFill, rule.cancellousDensity);
        nCancellous += std::uint64_t(span.x) * std::uint64_t(span.y) * std::uint64_t(span.z);
        continue;
      }
      VoxelGrid::Brick& b = grid.materialiseBrick(brick);
      // Bounds on each voxel centre's distance to the surface. Neighbouring centres are one
      // voxel apart, so the bounds of the voxels before it (x-1, y-1, z-1) widened by one
      // voxel bound it too; one exact distance settles a run of voxels around it.
      for (int z = lo.z; z < hi.z; ++z)
        for (int y = lo.y; y < hi.y; ++y)
          for (int x = lo.x; x < hi.x; ++x) {
            const glm::ivec3 ijk(x, y, z);
            const glm::ivec3 l = ijk - lo;
            const std::size_t local = std::size_t(VoxelGrid::voxelInBrick(l));
            double lower = 0.0;
            double upper = kUnbounded;
            for (int axis = 0; axis < 3; ++axis) {
              if (l[axis] == 0) continue;
              glm::ivec3 prev = l;
              --prev[axis];
              const std::size_t p = std::size_t(VoxelGrid::voxelInBrick(prev));
              lower = std::max(lower, lowerMm[p] - vs);
              upper = std::min(upper, upperMm[p] + vs);
            }
            if (upper > shellMm && lower <= shellMm && b.fill[local] != 0) {
              ++nQueries;
              const double d = surface.distanceWithin(grid.voxelCentreMm(ijk), queryReachMm);
              lower = d < 0.0 ? queryReachMm : d;
              upper = d < 0.0 ? kUnbounded : d;
            }
            lowerMm[local] = lower;
            upperMm[local] = upper;
            if (b.fill[local] == 0) {
              b.density[local] = 0;
              continue;
            }
            const bool isCortical = upper <= shellMm;
            b.density[local] = isCortical ? rule.corticalDensity : rule.cancellousDensity;
            (isCortical ? nCortical : nCancellous) += 1;
          }
    }
    corticalCount += nCortical;
    cancellousCount += nCancellous;
    queryCount += nQueries;
  });
  grid.compact();
  return DensityStats{corticalCount.load(), cancellousCount.load(), queryCount.load()};
}

}  // namespace osteon::geometry
