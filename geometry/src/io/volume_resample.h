// Resampling a stored volume onto a cubic OutputGrid (volume_meaning.h): an output voxel's
// stored position is affine in its index, so a row of them steps along it, sampled in float
// (doubles for 64-bit values); and an output brick whose trilinear footprint holds stored values
// all on one side of what matters (the ramp, the cortical threshold, a label) takes its one fill
// without a voxel sampled: the stored values' range is kept per block of kRangeEdge^3.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "io/volume_grid_build.h"
#include "io/volume_sampling.h"

namespace osteon::geometry {

// Sampled in float, which holds 8 to 32-bit values and their fills well; 64-bit ones in double.
template <typename T>
using SampleOf = std::conditional_t<sizeof(T) == 8, double, float>;

// The continuous stored index of output voxel p's centre: start + p.x step[0] + p.y step[1] +
// p.z step[2].
struct IndexMap {
  glm::dvec3 start{0.0};
  glm::dvec3 step[3];
  glm::dvec3 at(glm::dvec3 p) const {
    return start + p.x * step[0] + p.y * step[1] + p.z * step[2];
  }
  // The same map for points `offset` (in output voxels) from each voxel's centre.
  IndexMap shifted(glm::dvec3 offset) const {
    IndexMap m = *this;
    m.start = at(offset);
    return m;
  }
};

inline IndexMap indexMap(const OutputGrid& g) {
  IndexMap m;
  m.start = g.storedIndex(g.centreMm(glm::ivec3(0)));
  for (int a = 0; a < 3; ++a) m.step[a] = g.lpsToIndex[a] * g.voxelSizeMm;
  return m;
}

// A value as a sample: values past +-1e30 (no scanner's) are clamped there in float rather than
// made infinite, whose differences are not numbers.
template <typename Sample>
Sample asSample(double v) {
  if constexpr (std::is_same_v<Sample, float>) return float(std::clamp(v, -1e30, 1e30));
  return Sample(v);
}

// The trilinear values of value(stored) at `length` voxels of a row from `start`, each from the
// 8 stored voxels round it (the edge's within half a voxel of the stored grid, `outside` past it).
template <typename T, typename Value, typename Sample>
void trilinearRow(const OutputGrid& g, const IndexMap& m, StoredValues<T> values,
                  const Value& value, Sample outside, glm::ivec3 start, int length, Sample* out) {
  using V = glm::vec<3, Sample>;
  const V q0(m.at(glm::dvec3(start))), dq(m.step[0]);
  const V last(g.stored - 1), lowest(Sample(-0.5)), highest = last + Sample(0.5);
  const glm::ivec3 top = glm::max(g.stored - 2, 0);
  const std::size_t sy = std::size_t(g.stored.x), sz = sy * std::size_t(g.stored.y);
  const std::size_t ox = g.stored.x > 1 ? 1 : 0, oy = g.stored.y > 1 ? sy : 0,
                    oz = g.stored.z > 1 ? sz : 0;
  for (int x = 0; x < length; ++x) {
    V q = q0 + Sample(x) * dq;
    if (!(q.x >= lowest.x && q.y >= lowest.y && q.z >= lowest.z && q.x <= highest.x &&
          q.y <= highest.y && q.z <= highest.z)) {
      out[x] = outside;
      continue;
    }
    q = glm::clamp(q, V(0), last);
    const glm::ivec3 i0 = glm::min(glm::ivec3(q), top);
    const V t = q - V(i0);
    const std::size_t s = std::size_t(i0.z) * sz + std::size_t(i0.y) * sy + std::size_t(i0.x);
    const auto at = [&](std::size_t k) { return Sample(value(values[k])); };
    const auto lerp = [](Sample a, Sample b, Sample w) { return a + w * (b - a); };
    const Sample y0 =
        lerp(lerp(at(s), at(s + ox), t.x), lerp(at(s + oy), at(s + oy + ox), t.x), t.y);
    const Sample y1 = lerp(lerp(at(s + oz), at(s + oz + ox), t.x),
                           lerp(at(s + oz + oy), at(s + oz + oy + ox), t.x), t.y);
    out[x] = lerp(y0, y1, t.z);
  }
}

// The range of value(stored) over each output brick's trilinear footprint (the stored voxels
// its voxels' samples read, `outside` joined where one lies past the stored grid), from the
// ranges of stored blocks of kRangeEdge^3: wider than the footprint's at worst, never narrower.
template <typename Sample>
struct BrickRanges {
  glm::ivec3 bricks{0};
  std::vector<std::pair<Sample, Sample>> range;  // per output brick, x fastest
  const std::pair<Sample, Sample>& of(glm::ivec3 b) const {
    return range[(std::size_t(b.z) * std::size_t(bricks.y) + std::size_t(b.y)) *
                     std::size_t(bricks.x) +
                 std::size_t(b.x)];
  }
};

inline constexpr int kRangeEdge = 8;
// A label map's resampled voxel: its share of the bone from kLabelSubsamples^3 samples.
inline constexpr int kLabelSubsamples = 3;

// The range of value(stored) over each stored block of kRangeEdge^3 (x fastest), slabs of
// blocks in parallel.
template <typename T, typename Value, typename Sample>
std::vector<std::pair<Sample, Sample>> storedBlockRanges(glm::ivec3 n, StoredValues<T> values,
                                                         const Value& value, glm::ivec3 blocks) {
  std::vector<std::pair<Sample, Sample>> range(std::size_t(blocks.x) * std::size_t(blocks.y) *
                                               std::size_t(blocks.z));
  tbb::parallel_for(tbb::blocked_range<int>(0, blocks.z), [&](const tbb::blocked_range<int>& bz) {
    std::vector<Sample> lo(std::size_t(blocks.x)), hi(std::size_t(blocks.x));
    for (int b = bz.begin(); b < bz.end(); ++b) {
      for (int by = 0; by < blocks.y; ++by) {
        std::fill(lo.begin(), lo.end(), Sample(INFINITY));
        std::fill(hi.begin(), hi.end(), Sample(-INFINITY));
        const int z1 = std::min(n.z, (b + 1) * kRangeEdge),
                  y1 = std::min(n.y, (by + 1) * kRangeEdge);
        for (int z = b * kRangeEdge; z < z1; ++z) {
          for (int y = by * kRangeEdge; y < y1; ++y) {
            const std::size_t row =
                (std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x);
            for (int x0 = 0; x0 < n.x; x0 += kRangeEdge) {
              Sample l = lo[std::size_t(x0 / kRangeEdge)], h = hi[std::size_t(x0 / kRangeEdge)];
              const int x1 = std::min(n.x, x0 + kRangeEdge);
              for (int x = x0; x < x1; ++x) {
                const Sample v = Sample(value(values[row + std::size_t(x)]));
                l = v < l ? v : l;
                h = v > h ? v : h;
              }
              lo[std::size_t(x0 / kRangeEdge)] = l;
              hi[std::size_t(x0 / kRangeEdge)] = h;
            }
          }
        }
        const std::size_t at =
            (std::size_t(b) * std::size_t(blocks.y) + std::size_t(by)) * std::size_t(blocks.x);
        for (int bx = 0; bx < blocks.x; ++bx)
          range[at + std::size_t(bx)] = {lo[std::size_t(bx)], hi[std::size_t(bx)]};
      }
    }
  });
  return range;
}

template <typename T, typename Value, typename Sample>
BrickRanges<Sample> brickRanges(const OutputGrid& g, const IndexMap& m, StoredValues<T> values,
                                const Value& value, Sample outside, double reachVoxels) {
  const glm::ivec3 blocks = (g.stored + kRangeEdge - 1) / kRangeEdge;
  const auto stored = storedBlockRanges<T, Value, Sample>(g.stored, values, value, blocks);
  BrickRanges<Sample> r;
  r.bricks = (g.sizes + kBrickEdge - 1) / kBrickEdge;
  r.range.resize(std::size_t(r.bricks.x) * std::size_t(r.bricks.y) * std::size_t(r.bricks.z));
  forEachVoxel(r.bricks, [&](glm::ivec3 b, std::size_t i) {
    const glm::ivec3 p0 = b * kBrickEdge, p1 = glm::min(p0 + kBrickEdge, g.sizes) - 1;
    // The brick's sample points span its voxel centres, `reachVoxels` wider on every side.
    const glm::dvec3 c0 = glm::dvec3(p0) - reachVoxels, c1 = glm::dvec3(p1) + reachVoxels;
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (int c = 0; c < 8; ++c) {
      const glm::dvec3 q =
          m.at({(c & 1) ? c1.x : c0.x, (c & 2) ? c1.y : c0.y, (c & 4) ? c1.z : c0.z});
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    // A margin for the samples' float positions; past the edge by half a voxel: `outside`.
    lo -= 1e-3;
    hi += 1e-3;
    const glm::dvec3 last(g.stored - 1);
    const bool past =
        glm::any(glm::lessThan(lo, glm::dvec3(-0.5))) || glm::any(glm::greaterThan(hi, last + 0.5));
    const glm::ivec3 s0 =
        glm::ivec3(glm::clamp(glm::floor(lo), glm::dvec3(0.0), last)) / kRangeEdge;
    const glm::ivec3 s1 =
        glm::ivec3(glm::clamp(glm::floor(hi) + 1.0, glm::dvec3(0.0), last)) / kRangeEdge;
    Sample l = past ? outside : Sample(INFINITY), h = past ? outside : Sample(-INFINITY);
    for (int z = s0.z; z <= s1.z; ++z) {
      for (int y = s0.y; y <= s1.y; ++y) {
        for (int x = s0.x; x <= s1.x; ++x) {
          const auto& [bl, bh] = stored[(std::size_t(z) * std::size_t(blocks.y) + std::size_t(y)) *
                                            std::size_t(blocks.x) +
                                        std::size_t(x)];
          l = std::min(l, bl);
          h = std::max(h, bh);
        }
      }
    }
    r.range[i] = {l, h};
  });
  return r;
}

// A sample's float rounding, from the lowest and highest values met: the margin by which a
// brick's range is widened before it is called uniform.
template <typename Sample>
Sample sampleMargin(Sample lo, Sample hi) {
  return (std::abs(lo) + std::abs(hi)) * Sample(1e-5) + Sample(1e-6);
}

// As buildGrid, but a brick wholly within the grid for which uniform(brick, fill, density) is
// true is set so without a voxel worked out; voxelRow gives the voxels of the others a brick's
// row at a time (at most kBrickEdge from start.x, within the grid). Returns the voxels inside.
template <typename Uniform, typename VoxelRow>
std::uint64_t buildGridByBrick(VoxelGrid& grid, const Uniform& uniform, const VoxelRow& voxelRow) {
  const glm::ivec3 n = grid.dims(), nb = grid.brickDims();
  std::atomic<std::uint64_t> inside{0};
  tbb::parallel_for(
      tbb::blocked_range<int>(0, nb.y * nb.z), [&](const tbb::blocked_range<int>& rs) {
        BrickRow one(1);
        std::uint64_t rowsInside = 0;
        for (int r = rs.begin(); r < rs.end(); ++r) {
          for (int bx = 0; bx < nb.x; ++bx) {
            const glm::ivec3 b(bx, r % nb.y, r / nb.y), p0 = b * kBrickEdge;
            const glm::ivec3 size = glm::min(n - p0, kBrickEdge);
            const std::size_t brick = grid.brickIndex(b);
            Fill fill = 0;
            Density density = 0;
            const bool whole = size == glm::ivec3(kBrickEdge);
            if (whole && uniform(b, fill, density)) {
              grid.setBrickUniform(brick, fill, density);
              rowsInside += fill >= kFillHalf ? kBrickVoxels : 0;
              continue;
            }
            if (!whole) {
              std::fill(one.fill.begin(), one.fill.end(), Fill(0));
              std::fill(one.density.begin(), one.density.end(), Density(0));
            }
            for (int z = 0; z < size.z; ++z) {
              for (int y = 0; y < size.y; ++y) {
                const glm::ivec3 p = p0 + glm::ivec3(0, y, z);
                const std::size_t i =
                    (std::size_t(p.z) * std::size_t(n.y) + std::size_t(p.y)) * std::size_t(n.x) +
                    std::size_t(p.x);
                const std::size_t at = one.at(0, y, z);
                voxelRow(p, i, size.x, &one.fill[at], &one.density[at]);
              }
            }
            rowsInside += storeBrick(grid, brick, one, 0);
          }
        }
        inside += rowsInside;
      });
  grid.clearDirty();
  return inside.load();
}

// The fills of a resampled grid, held whole (x fastest): fillOf(sample), non-decreasing, of each
// voxel's trilinear sample of value(stored) at its centre, or with `subsamples` the mean of
// subsamples^3 of them spread evenly over the voxel; bricks by their ranges where uniform.
template <typename T, typename Value, typename Sample, typename FillOf>
std::vector<Fill> resampledFills(const OutputGrid& g, StoredValues<T> values, const Value& value,
                                 Sample outside, const FillOf& fillOf, int subsamples = 1) {
  const IndexMap centres = indexMap(g);
  std::vector<IndexMap> maps;
  for (int k = 0; k < subsamples * subsamples * subsamples; ++k) {
    const glm::ivec3 s(k % subsamples, k / subsamples % subsamples, k / subsamples / subsamples);
    maps.push_back(centres.shifted((glm::dvec3(s) + 0.5) / double(subsamples) - 0.5));
  }
  const double reach = 0.5 - 0.5 / double(subsamples);
  const BrickRanges<Sample> ranges = brickRanges(g, centres, values, value, outside, reach);
  const Sample share = Sample(1) / Sample(maps.size());
  std::vector<Fill> fills(g.count());
  forEachVoxel(ranges.bricks, [&](glm::ivec3 b, std::size_t) {
    const auto [lo, hi] = ranges.of(b);
    const Sample margin = sampleMargin(lo, hi);
    const Fill low = fillOf(lo - margin), high = fillOf(hi + margin);
    const glm::ivec3 p0 = b * kBrickEdge, size = glm::min(g.sizes - p0, kBrickEdge);
    Sample row[kBrickEdge], sum[kBrickEdge];
    for (int z = p0.z; z < p0.z + size.z; ++z) {
      for (int y = p0.y; y < p0.y + size.y; ++y) {
        Fill* out =
            fills.data() +
            (std::size_t(z) * std::size_t(g.sizes.y) + std::size_t(y)) * std::size_t(g.sizes.x) +
            std::size_t(p0.x);
        if (low == high) {
          std::fill_n(out, size.x, low);
          continue;
        }
        std::fill_n(sum, kBrickEdge, Sample(0));
        for (const IndexMap& m : maps) {
          trilinearRow(g, m, values, value, outside, {p0.x, y, z}, size.x, row);
          for (int x = 0; x < size.x; ++x) sum[x] += row[x];
        }
        for (int x = 0; x < size.x; ++x) out[x] = fillOf(sum[x] * share);
      }
    }
  });
  return fills;
}

}  // namespace osteon::geometry
