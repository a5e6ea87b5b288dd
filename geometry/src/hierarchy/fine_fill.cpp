// Level -2 fill of the voxels the surface passes through, from the mesh (FineFillSource).
#include "osteon/geometry/hierarchy/fine_fill.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "osteon/geometry/voxels/embree_scene.h"
#include "sub_fill.h"
#include "voxels/column_ray.h"

namespace osteon::geometry {

namespace {

std::uint64_t linearIndex(const glm::ivec3& v, const glm::ivec3& dims) {
  return std::uint64_t(v.x) +
         std::uint64_t(dims.x) * (std::uint64_t(v.y) + std::uint64_t(dims.y) * std::uint64_t(v.z));
}

struct Entry {
  std::uint64_t column;  // x + nx * y
  int z;
};

// The grid's partial voxels (0 < fill < full), sorted by (x, y) column, then z.
std::vector<Entry> partialVoxels(const VoxelGrid& grid) {
  const glm::ivec3 dims = grid.dims();
  constexpr int B = VoxelGrid::kBrickSize;
  std::vector<Entry> entries;
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    const VoxelGrid::Brick* b = grid.brickData(brick);
    if (!b) continue;  // uniform bricks are empty or full throughout
    const glm::ivec3 lo = grid.brickCoord(brick) * B;
    const glm::ivec3 hi = glm::min(lo + B, dims);
    for (int z = lo.z; z < hi.z; ++z)
      for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x) {
          const Fill f = b->fill[std::size_t(VoxelGrid::voxelInBrick(glm::ivec3(x, y, z) - lo))];
          if (f > 0 && f < kFillFull) {
            entries.push_back({std::uint64_t(x) + std::uint64_t(dims.x) * std::uint64_t(y), z});
          }
        }
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.column != b.column ? a.column < b.column : a.z < b.z;
  });
  return entries;
}

// Adds to a voxel's sub-voxel tallies the part of each interval (along z, from the ray's start)
// that lies in sub-voxels (sx, sy, 0..) of the voxel whose bottom is baseMm along the ray.
void addOverlaps(const std::vector<detail::Interval>& intervals, double baseMm, double subMm,
                 int sx, int sy, float* voxelAcc) {
  for (const detail::Interval& in : intervals) {
    // Interval ends in sub-voxel units from the bottom of this voxel.
    const double s0 = std::max(0.0, (in.t0 - baseMm) / subMm);
    const double s1 = std::min(double(kSubPerEdge), (in.t1 - baseMm) / subMm);
    for (int sz = int(s0); sz < kSubPerEdge && sz < s1; ++sz) {
      const double overlap = std::min(s1, sz + 1.0) - std::max(s0, double(sz));
      if (overlap > 0.0) {
        voxelAcc[std::size_t(sx + kSubPerEdge * (sy + kSubPerEdge * sz))] += float(overlap);
      }
    }
  }
}

}  // namespace

FineFillSource FineFillSource::sample(const VoxelGrid& grid, const TriangleMesh& mesh,
                                      const EmbreeScene& surface, int raysPerSubAxis) {
  FineFillSource source;
  source.dims_ = grid.dims();
  const glm::ivec3 dims = grid.dims();

  // The partial voxels, grouped by (x, y) column so one set of rays serves a whole column.
  const std::vector<Entry> entries = partialVoxels(grid);
  std::vector<std::size_t> columnStart;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i == 0 || entries[i].column != entries[i - 1].column) columnStart.push_back(i);
  }
  columnStart.push_back(entries.size());

  std::vector<std::array<std::uint8_t, kSubVoxels>> subFill(entries.size());
  const int outwardSign = detail::outwardSignOf(mesh);
  const double vs = grid.voxelSizeMm();
  const glm::dvec3 origin = grid.originMm();
  const double start = origin.z - vs;
  const double length = (dims.z + 2) * vs;
  const int R = std::max(1, raysPerSubAxis);
  const double sub = vs / kSubPerEdge;

  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, columnStart.size() - 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        detail::ColumnRay ray(surface, 2, outwardSign, start, length, std::min(1e-4, 1e-3 * sub));
        std::vector<detail::Interval> intervals;
        std::vector<float> acc;
        for (std::size_t col = range.begin(); col != range.end(); ++col) {
          const std::size_t first = columnStart[col];
          const std::size_t last = columnStart[col + 1];
          const int x = int(entries[first].column % std::uint64_t(dims.x));
          const int y = int(entries[first].column / std::uint64_t(dims.x));
          acc.assign((last - first) * kSubVoxels, 0.f);
          for (int sy = 0; sy < kSubPerEdge; ++sy)
            for (int sx = 0; sx < kSubPerEdge; ++sx)
              for (int ry = 0; ry < R; ++ry)
                for (int rx = 0; rx < R; ++rx) {
                  // Stratified in the sub-column, nudged off rational positions as the voxelizer.
                  const double u = origin.x + x * vs + (sx + (rx + 0.5 + 0.0061803) / R) * sub;
                  const double v = origin.y + y * vs + (sy + (ry + 0.5 + 0.0041421) / R) * sub;
                  int attempts = 0;
                  if (ray.cast(u, v, 2e-3 * sub / R, intervals, attempts) ==
                      detail::RayOutcome::Unresolved) {
                    detail::pairByParity(ray.hits(), intervals);
                  }
                  for (std::size_t e = first; e < last; ++e) {
                    const double base = (entries[e].z + 1) * vs;  // ray starts one voxel below
                    addOverlaps(intervals, base, sub, sx, sy, &acc[(e - first) * kSubVoxels]);
                  }
                }
          for (std::size_t e = first; e < last; ++e) {
            std::array<std::uint8_t, kSubVoxels> sampled;
            for (int i = 0; i < kSubVoxels; ++i) {
              const float fraction = acc[(e - first) * kSubVoxels + std::size_t(i)] / float(R * R);
              sampled[std::size_t(i)] =
                  std::uint8_t(std::clamp(std::lround(fraction * 255.f), 0L, 255L));
            }
            // Fitted now to sum exactly to the voxel's fill, so refining only copies them.
            const glm::ivec3 v(x, y, entries[e].z);
            std::array<Fill, kSubVoxels> fitted;
            detail::fitToTotal(sampled, grid.fill(v), fitted);
            for (int i = 0; i < kSubVoxels; ++i)
              subFill[e][std::size_t(i)] = std::uint8_t(fitted[std::size_t(i)]);
          }
        }
      });

  // Sorted by grid linear index for binary search.
  std::vector<std::uint32_t> order(entries.size());
  std::iota(order.begin(), order.end(), 0u);
  const auto keyOf = [&](std::uint32_t i) {
    const glm::ivec3 v(int(entries[i].column % std::uint64_t(dims.x)),
                       int(entries[i].column / std::uint64_t(dims.x)), entries[i].z);
    return linearIndex(v, dims);
  };
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return keyOf(a) < keyOf(b); });
  source.keys_.reserve(order.size());
  source.subFill_.reserve(order.size());
  source.sampledFill_.reserve(order.size());
  for (const std::uint32_t i : order) {
    source.keys_.push_back(keyOf(i));
    source.subFill_.push_back(subFill[i]);
    const glm::ivec3 v(int(entries[i].column % std::uint64_t(dims.x)),
                       int(entries[i].column / std::uint64_t(dims.x)), entries[i].z);
    source.sampledFill_.push_back(grid.fill(v));
  }
  return source;
}

bool FineFillSource::find(const glm::ivec3& v, std::array<std::uint8_t, kSubVoxels>& subFill,
                          Fill& sampledFill) const {
  if (keys_.empty()) return false;
  const std::uint64_t key = linearIndex(v, dims_);
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it == keys_.end() || *it != key) return false;
  const std::size_t i = std::size_t(it - keys_.begin());
  subFill = subFill_[i];
  sampledFill = sampledFill_[i];
  return true;
}

std::size_t FineFillSource::memoryBytes() const {
  return sizeof(*this) + keys_.capacity() * sizeof(std::uint64_t) +
         subFill_.capacity() * sizeof(std::array<std::uint8_t, kSubVoxels>) +
         sampledFill_.capacity() * sizeof(Fill);
}

}  // namespace osteon::geometry
