#include "osteon/geometry/voxels/density.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/option_error.h"
#include "osteon/geometry/voxels/embree_scene.h"

namespace osteon::geometry {

// Brick edge in voxels.
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

void validateDensityRule(const DensityRule& rule) {
  if (!std::isfinite(rule.corticalThicknessMm) || rule.corticalThicknessMm < 0.0) {
    std::ostringstream value;
    value << rule.corticalThicknessMm;
    throw OptionError("corticalThicknessMm", value.str(), "must be a finite thickness >= 0");
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
    {{-1, 0, 0}, 0},
    {{0, -1, 0}, 0},
    {{0, 0, -1}, 0},
    {{-1, -1, 0}, 1},
    {{1, -1, 0}, 1},
    {{-1, 0, -1}, 1},
    {{1, 0, -1}, 1},
    {{0, -1, -1}, 1},
    {{0, 1, -1}, 1},
    {{-1, -1, -1}, 2},
    {{1, -1, -1}, 2},
    {{-1, 1, -1}, 2},
    {{1, 1, -1}, 2},
}};

// Bounds of a brick's voxels, padded by one voxel on every side the visited neighbours reach
// (x and y both ways, z below) so that no neighbour needs a range check: padding holds the
// bounds that bound nothing (0 and infinity).
constexpr int kPad = kBrickEdge + 2;
constexpr int kPaddedVoxels = kPad * kPad * (kBrickEdge + 1);
constexpr int paddedIndex(int x, int y, int z) {
  return (x + 1) + kPad * ((y + 1) + kPad * (z + 1));
}

constexpr std::size_t kMaxNearTriangles = 1024;

// A triangle near a brick, with its bounding box for a quick rejection.
struct NearTriangle {
  double fromCentre;  // lower bound on its distance from the brick centre (box distance)
  glm::dvec3 a, b, c;
  glm::dvec3 lo, hi;
};

inline double boxDistance(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
  double box2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e = std::max(0.0, std::max(lo[k] - p[k], p[k] - hi[k]));
    box2 += e * e;
  }
  return box2;
}

// What EmbreeScene::distanceWithin(point, reach) answers, over the triangles near the brick
// (a superset of every triangle within reach of its voxels): the smallest distance below
// reach, else -1. The minimum is the same whatever the order, so the same bits.
// `near` is sorted by fromCentre and p lies within pFromCentre of the brick centre, so a
// triangle is at least fromCentre - pFromCentre from p: the scan stops at the first one that
// cannot beat the best so far.
// upperMm: a bound the distance is known not to exceed (it only starts the search tighter:
// a triangle nearer than reach is still found and the minimum is the same).
// stopAtMm: return the first distance found at or below it (then only an upper bound: *exact
// is false), since that already decides the voxel.
inline double distanceWithinNear(const std::vector<NearTriangle>& near, const glm::dvec3& p,
                                 double pFromCentre, double reach, double upperMm, double stopAtMm,
                                 bool* exact) {
  *exact = true;
  double best = reach;
  double search = std::min(reach, upperMm * (1.0 + 1e-9) + 1e-9);
  bool found = false;
  for (const NearTriangle& t : near) {
    // Margins far above rounding: a skipped triangle is never a winner.
    const double reject = std::min(best, search) * (1.0 + 1e-9) + 1e-9;
    if (t.fromCentre - pFromCentre * (1.0 + 1e-9) > reject) break;
    if (boxDistance(p, t.lo, t.hi) > reject * reject) continue;
    const double d = glm::length(closestPointOnTriangle(p, t.a, t.b, t.c) - p);
    if (d < best) {
      best = d;
      found = true;
      if (d <= stopAtMm) {
        *exact = false;
        return d;
      }
    }
  }
  return found ? best : -1.0;
}

// Distance of each voxel centre of a whole brick from the brick's centre (mm).
std::array<double, VoxelGrid::kBrickVoxels> brickRadii(double voxelSizeMm) {
  std::array<double, VoxelGrid::kBrickVoxels> radius{};
  for (int z = 0; z < kBrickEdge; ++z)
    for (int y = 0; y < kBrickEdge; ++y)
      for (int x = 0; x < kBrickEdge; ++x) {
        const glm::dvec3 offset = glm::dvec3(x, y, z) + 0.5 - 0.5 * double(kBrickEdge);
        radius[std::size_t(VoxelGrid::voxelInBrick({x, y, z}))] = voxelSizeMm * glm::length(offset);
      }
  return radius;
}

// The triangles within reachMm of a brick's centre, nearest box first, in `near`; false (and
// `near` unspecified) when there are more than kMaxNearTriangles.
bool gatherNear(const EmbreeScene& surface, const glm::dvec3& centre, double reachMm,
                std::vector<std::uint32_t>& nearIds, std::vector<NearTriangle>& near) {
  near.clear();
  nearIds.clear();
  surface.trianglesNear(centre, reachMm, nearIds);
  std::sort(nearIds.begin(), nearIds.end());
  nearIds.erase(std::unique(nearIds.begin(), nearIds.end()), nearIds.end());
  if (nearIds.size() > kMaxNearTriangles) return false;
  const TriangleMesh& mesh = surface.mesh();
  for (const std::uint32_t id : nearIds) {
    const glm::u32vec3& t = mesh.triangles[id];
    const glm::dvec3& pa = mesh.positionsMm[t.x];
    const glm::dvec3& pb = mesh.positionsMm[t.y];
    const glm::dvec3& pc = mesh.positionsMm[t.z];
    const glm::dvec3 tlo = glm::min(pa, glm::min(pb, pc));
    const glm::dvec3 thi = glm::max(pa, glm::max(pb, pc));
    near.push_back({std::sqrt(boxDistance(centre, tlo, thi)), pa, pb, pc, tlo, thi});
  }
  std::sort(near.begin(), near.end(), [](const NearTriangle& p, const NearTriangle& q) {
    return p.fromCentre < q.fromCentre;
  });
  return true;
}

// The 13 visited neighbours' offsets in the padded bounds arrays.
std::array<int, 13> visitedNeighbourDeltas() {
  std::array<int, 13> delta{};
  for (std::size_t n = 0; n < kVisitedNeighbours.size(); ++n) {
    const glm::ivec3 o = kVisitedNeighbours[n].offset;
    delta[n] = paddedIndex(o.x, o.y, o.z) - paddedIndex(0, 0, 0);
  }
  return delta;
}

}  // namespace

// Brick by brick: a brick whose centre is deep inside stays uniform and cancellous. In any
// other, bounds on each voxel centre's distance to the surface (the distance is 1-Lipschitz)
// come from the brick centre's distance (or, when that found nothing within brickReachMm, from
// that reach), and from the 13 neighbours already visited in this brick, widened by the
// distance to them (1, sqrt 2 or sqrt 3 voxels). A voxel whose bounds do not decide it gets one
// exact distance, which then bounds the voxels after it. Every triangle within queryReachMm of
// a voxel centre is within that plus the farthest centre's distance of the brick centre: they
// are gathered once for the brick and scanned for each voxel's query. Large bricks (coarse
// voxels, whose gather would be wider than twice a voxel's reach) or crowded ones are left to
// Embree's closest-first search for each voxel instead.
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
  const std::array<double, VoxelGrid::kBrickVoxels> fullBrickRadius = brickRadii(vs);
  const std::array<int, 13> neighbourDelta = visitedNeighbourDeltas();
  std::atomic<std::uint64_t> corticalCount{0}, cancellousCount{0}, queryCount{0};

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, grid.brickCount()),
      [&](const tbb::blocked_range<std::size_t>& range) {
        std::uint64_t nCortical = 0, nCancellous = 0, nQueries = 0;
        std::vector<double> lowerMm(kPaddedVoxels, 0.0);
        std::vector<double> upperMm(kPaddedVoxels, kUnbounded);
        bool interiorStale = false;  // a partial brick left values where padding must be
        std::vector<std::uint32_t> nearIds;
        std::vector<NearTriangle> near;
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
          const glm::dvec3 centreGrid = glm::dvec3(lo) + 0.5 * glm::dvec3(span);
          const bool fullBrick = span == glm::ivec3(kBrickEdge);
          if (!fullBrick || interiorStale) {
            // Voxels past a partial brick's span are neighbours that bound nothing.
            std::fill(lowerMm.begin(), lowerMm.end(), 0.0);
            std::fill(upperMm.begin(), upperMm.end(), kUnbounded);
          }
          interiorStale = !fullBrick;
          const double farthestMm = vs * glm::length(0.5 * glm::dvec3(span) - 0.5);
          const bool useNear =
              farthestMm <= queryReachMm &&
              gatherNear(surface, centre, queryReachMm + farthestMm, nearIds, near);
          if (!useNear) near.clear();
          for (int z = lo.z; z < hi.z; ++z)
            for (int y = lo.y; y < hi.y; ++y)
              for (int x = lo.x; x < hi.x; ++x) {
                const glm::ivec3 ijk(x, y, z);
                const glm::ivec3 l = ijk - lo;
                const std::size_t local = std::size_t(VoxelGrid::voxelInBrick(l));
                const double r = fullBrick ? fullBrickRadius[local]
                                           : vs * glm::length(glm::dvec3(ijk) + 0.5 - centreGrid);
                double lower = centreDistance < 0.0 ? brickReachMm - r : centreDistance - r;
                double upper = centreDistance < 0.0 ? kUnbounded : centreDistance + r;
                const int pi = paddedIndex(l.x, l.y, l.z);
                for (int n = 0; n < 13; ++n) {
                  const int p = pi + neighbourDelta[std::size_t(n)];
                  const double step = stepMm[kVisitedNeighbours[std::size_t(n)].kind];
                  lower = std::max(lower, lowerMm[std::size_t(p)] - step);
                  upper = std::min(upper, upperMm[std::size_t(p)] + step);
                }
                if (upper > shellMm && lower <= shellMm && b.fill[local] != 0) {
                  ++nQueries;
                  bool exact = true;
                  const double d =
                      useNear ? distanceWithinNear(near, grid.voxelCentreMm(ijk), r, queryReachMm,
                                                   upper, shellMm, &exact)
                              : surface.distanceWithin(grid.voxelCentreMm(ijk), queryReachMm);
                  if (exact) lower = d < 0.0 ? queryReachMm : d;
                  upper = d < 0.0 ? kUnbounded : d;
                }
                lowerMm[std::size_t(pi)] = lower;
                upperMm[std::size_t(pi)] = upper;
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
