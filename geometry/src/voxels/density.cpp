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

namespace {

// The 13 of a voxel's 26 neighbours that come before it in x-fastest order, and how far they
// are (kind 0: one voxel, 1: sqrt 2, 2: sqrt 3 voxels).
struct Neighbour {
  glm::ivec3 offset;
  int kind;
};
constexpr std::array<Neighbour, 13> kVisitedNeighbours{{
    {{-1, 0, 0}, 0}, {{0, -1, 0}, 0}, {{0, 0, -1}, 0},
    {{-1, -1, 0}, 1}, {{1, -1, 0}, 1}, {{-1, 0, -1}, 1}, {{1, 0, -1}, 1}, {{0, -1, -1}, 1},
    {{0, 1, -1}, 1},
    {{-1, -1, -1}, 2}, {{1, -1, -1}, 2}, {{-1, 1, -1}, 2}, {{1, 1, -1}, 2},
}};

}  // namespace

DensityStats assignDensity(VoxelGrid& grid, const EmbreeScene& surface, const DensityRule& rule) {
  validateDensityRule(rule);
  const glm::ivec3 dims = grid.dims();
  const double vs = grid.voxelSizeMm();
  const double shellMm = rule.corticalThicknessMm;
  // A brick whose centre is farther than this from the surface holds no cortical voxel.
  const double brickReachMm = shellMm + 0.5 * std::sqrt(3.0) * kBrickEdge * vs;
  // Voxel queries look a little past the shell so that a miss still bounds the next voxels.
  const double queryReachMm = shellMm + 2.0 * vs;
  const double stepMm[3] = {vs, std::sqrt(2.0) * vs, std::sqrt(3.0) * vs};
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
      const double centreDistance = surface.distanceWithin(centre, brickReachMm);
      if (centreDistance < 0.0 && !allocated) {
        // Deep inside: the whole brick is cancellous and stays a few bytes.
        grid.setBrickUniform(brick, uniformFill, rule.cancellousDensity);
        nCancellous += std::uint64_t(span.x) * std::uint64_t(span.y) * std::uint64_t(span.z);
        continue;
      }
      VoxelGrid::Brick& b = grid.materialiseBrick(brick);
      // Bounds on each voxel centre's distance to the surface (the distance is 1-Lipschitz):
      // from the brick centre's distance (or, when that found nothing within brickReachMm,
      // from that reach), and from the 13 neighbours already visited in this brick, widened
      // by the distance to them (1, sqrt 2 or sqrt 3 voxels). A voxel whose bounds do not
      // decide it gets one exact distance, which then bounds the voxels after it.
      const glm::dvec3 centreGrid = glm::dvec3(lo) + 0.5 * glm::dvec3(span);
      for (int z = lo.z; z < hi.z; ++z)
        for (int y = lo.y; y < hi.y; ++y)
          for (int x = lo.x; x < hi.x; ++x) {
            const glm::ivec3 ijk(x, y, z);
            const glm::ivec3 l = ijk - lo;
            const std::size_t local = std::size_t(VoxelGrid::voxelInBrick(l));
            const double r = vs * glm::length(glm::dvec3(ijk) + 0.5 - centreGrid);
            double lower = centreDistance < 0.0 ? brickReachMm - r : centreDistance - r;
            double upper = centreDistance < 0.0 ? kUnbounded : centreDistance + r;
            for (const Neighbour& n : kVisitedNeighbours) {
              const glm::ivec3 prev = l + n.offset;
              if (prev.x < 0 || prev.y < 0 || prev.z < 0 || prev.x >= span.x || prev.y >= span.y) {
                continue;
              }
              const std::size_t p = std::size_t(VoxelGrid::voxelInBrick(prev));
              const double step = stepMm[n.kind];
              lower = std::max(lower, lowerMm[p] - step);
              upper = std::min(upper, upperMm[p] + step);
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
