// What a volume's values mean, kind by kind (volume_io.h; used by volume_load.cpp only): the
// values' summary, and the grid built from a label map, a CT or a scalar volume onto the
// OutputGrid (placed exactly or resampled).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "io/volume_grid_build.h"
#include "io/volume_resample.h"
#include "io/volume_sampling.h"
#include "osteon/core/error.h"
#include "osteon/core/number_text.h"
#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry {

// The range and, up to kMaxLabels + 1 of them, the distinct values and their counts.
template <typename T>
struct ValueSummary {
  T lo{}, hi{};
  std::map<T, std::uint64_t> counts;
  bool many = false;  // more than kMaxLabels distinct values
};

// The summary of values [begin, end): a piece of summarise's.
template <typename T>
ValueSummary<T> summarisePiece(StoredValues<T> values, std::size_t begin, std::size_t end) {
  ValueSummary<T> s;
  // The range in a pass of its own, which the compiler vectorises.
  T lo = values[begin], hi = lo;
  for (std::size_t i = begin; i < end; ++i) {
    const T x = values[i];
    lo = x < lo ? x : lo;
    hi = x > hi ? x : hi;
  }
  s.lo = lo;
  s.hi = hi;
  if constexpr (std::is_integral_v<T> && sizeof(T) <= 2) {
    // 8 and 16-bit values counted in a table of every value (a noisy CT's air changes value at
    // every voxel, a look-up in a map each), blocks of one value at once (a label map's runs).
    using Bits = std::make_unsigned_t<T>;
    std::vector<std::uint32_t> count(std::size_t(1) << (8 * sizeof(T)));
    constexpr std::size_t kBlock = 16;
    T pattern[kBlock];
    std::fill_n(pattern, kBlock, values[begin]);
    for (std::size_t i = begin; i < end;) {
      while (end - i >= kBlock &&
             std::memcmp(values.bytes + i * sizeof(T), pattern, sizeof(pattern)) == 0) {
        count[Bits(pattern[0])] += std::uint32_t(kBlock);
        i += kBlock;
      }
      const std::size_t stop = std::min(end, i + kBlock);
      for (; i < stop; ++i) ++count[Bits(values[i])];
      if (values[i - 1] != pattern[0]) std::fill_n(pattern, kBlock, values[i - 1]);
    }
    for (std::size_t k = 0; k < count.size() && !s.many; ++k) {
      if (count[k] == 0) continue;
      s.counts[T(Bits(k))] = count[k];
      s.many = s.counts.size() > std::size_t(kMaxLabels);
    }
    return s;
  }
  // The distinct values, until there are too many to be labels: blocks equal to the current
  // run throughout are counted at once (a vector compare: volumes are mostly long runs), then
  // value by value up to the next change.
  constexpr std::size_t kBlock = 16;
  T pattern[kBlock];  // the run's value, a block of it
  // Bytes equal are values equal (the values are finite: placeVolume refused the rest); values
  // equal in other bytes (-0 and 0) go value by value.
  const auto sameBlock = [&values, &pattern](std::size_t i) {
    return std::memcmp(values.bytes + i * sizeof(T), pattern, sizeof(pattern)) == 0;
  };
  T run = values[begin];
  std::fill_n(pattern, kBlock, run);
  std::uint64_t runLength = 0;
  for (std::size_t i = begin; i < end && !s.many;) {
    while (end - i >= kBlock && sameBlock(i)) {
      runLength += kBlock;
      i += kBlock;
    }
    const std::size_t stop = std::min(end, i + kBlock);
    while (i < stop && values[i] == run) {
      ++runLength;
      ++i;
    }
    if (i == stop) continue;
    s.counts[run] += runLength;
    s.many = s.counts.size() > std::size_t(kMaxLabels);
    run = values[i];
    std::fill_n(pattern, kBlock, run);
    runLength = 1;
    ++i;
  }
  if (!s.many) s.counts[run] += runLength;
  s.many = s.many || s.counts.size() > std::size_t(kMaxLabels);
  return s;
}

// The range and, up to kMaxLabels + 1 of them, the distinct values and their counts: pieces in
// parallel, joined in order (the result does not depend on the threads).
template <typename T>
ValueSummary<T> summarise(StoredValues<T> values, std::size_t count) {
  constexpr std::size_t kPieceValues = std::size_t(1) << 20;
  const std::size_t pieces = std::max<std::size_t>(1, (count + kPieceValues - 1) / kPieceValues);
  std::vector<ValueSummary<T>> piece(pieces);
  tbb::parallel_for(std::size_t(0), pieces, [&](std::size_t k) {
    piece[k] = summarisePiece(values, k * kPieceValues, std::min(count, (k + 1) * kPieceValues));
  });
  ValueSummary<T> s = std::move(piece[0]);
  for (std::size_t k = 1; k < pieces; ++k) {
    const ValueSummary<T>& p = piece[k];
    s.lo = p.lo < s.lo ? p.lo : s.lo;  // as the pass over all values would (NaN kept only first)
    s.hi = p.hi > s.hi ? p.hi : s.hi;
    s.many = s.many || p.many;
    for (const auto& [value, n] : p.counts) {
      if (s.many) break;
      s.counts[value] += n;
      s.many = s.counts.size() > std::size_t(kMaxLabels);
    }
  }
  return s;
}

// Labels are never negative (HU are): negative values make a volume a CT or nothing, so a CT of
// few values (air and bone) is not read as labels whose every non-zero voxel is bone. Floats are
// labels when every value is whole (masks saved as float); scaled values never are.
template <typename T>
bool isLabelMap(const ValueSummary<T>& s, const RawVolume& raw) {
  if (s.many) return false;
  if constexpr (std::is_floating_point_v<T>) {
    if (raw.slope != 1.0 || raw.intercept != 0.0) return false;
    for (const auto& [value, n] : s.counts) {
      if (!(value >= T(0) && value <= T(9007199254740992.0) && std::floor(value) == value))
        return false;
    }
    return true;
  } else {
    if (!raw.integer) return false;
    if constexpr (std::is_signed_v<T>) return !(s.lo < T(0));
    return true;
  }
}

// A volume whose every voxel is bone has no surface to drill: a misread volume, not a bone.
inline void refuseWholeBox(const std::string& path, std::uint64_t inside, std::uint64_t voxels,
                           const std::string& how) {
  if (inside < voxels) return;
  throw InputError(path + ": every voxel is bone: " + how +
                   "; not a plausible bone, which needs voxels outside it");
}

// Density by distance (label maps, scalar volumes): cortical within `shell` voxels of the
// outside (the volume's edge counts as outside) or at the surface (fill below half), cancellous
// deeper (deepInside).
inline Density distanceDensity(Fill fill, bool deep) {
  if (fill == 0) return 0;
  return deep ? kCtCancellousDensity : kCtCorticalDensity;
}

inline int shellVoxels(const VolumeOptions& options, const OutputGrid& g) {
  return int(std::clamp(std::ceil(options.corticalThicknessMm / g.voxelSizeMm), 1.0, 1e6));
}

// The fill rows of fills held whole (a resampled grid's).
inline auto heldFills(const std::vector<Fill>& fills) {
  return [&fills](glm::ivec3, std::size_t i, int length, Fill* out) {
    std::copy_n(fills.begin() + std::ptrdiff_t(i), length, out);
  };
}

// The fill of a value: 0 at iso - halfWidth, full at iso + halfWidth (a step when 0).
inline Fill rampFill(double value, double iso, double halfWidth) {
  if (!(halfWidth > 0.0)) return value >= iso ? kFillFull : Fill(0);
  const double t = (value - (iso - halfWidth)) / (2.0 * halfWidth);
  return Fill(std::lround(std::clamp(t, 0.0, 1.0) * kFillFull));
}

// The grid of a fill per voxel (fillRow(start, index, length, fills): a row at once), its
// density by the distance rule: cortical within the shell of voxels nearest the outside,
// cancellous deeper. Returns the voxels inside.
template <typename FillRow>
std::uint64_t buildByDistance(const OutputGrid& g, const FillRow& fillRow,
                              const VolumeOptions& options, VoxelGrid& grid) {
  const std::unique_ptr<std::uint8_t[]> deep =
      deepInside(g.sizes, shellVoxels(options, g), fillRow);
  const std::uint8_t* const deepAt = deep.get();
  return buildGrid(grid,
                   [&](glm::ivec3 p, std::size_t i, int length, Fill* fill, Density* density) {
                     fillRow(p, i, length, fill);
                     const std::uint8_t* d = deepAt + i;
                     for (int x = 0; x < length; ++x)
                       density[x] = distanceDensity(fill[x], d[x] != 0);
                   });
}

// Where a row of an exactly placed grid starts in the stored values (a row of them).
inline std::size_t storedRow(const OutputGrid& g, glm::ivec3 p, std::size_t i) {
  return g.whole ? i : g.storedOffset(p + g.offset);
}

// A label map's grid: each voxel 0 or full where placed exactly, its share inside where
// resampled; `inside` says which stored values are bone. Returns the voxels inside.
template <typename T, typename Inside>
std::uint64_t buildLabels(const OutputGrid& g, StoredValues<T> values, const Inside& inside,
                          const VolumeOptions& options, VoxelGrid& grid) {
  if (g.exact) {
    const auto fillRow = [&g, values, inside](glm::ivec3 p, std::size_t i, int length, Fill* out) {
      const std::size_t s = storedRow(g, p, i);
      for (int x = 0; x < length; ++x)
        out[x] = inside(values[s + std::size_t(x)]) ? kFillFull : Fill(0);
    };
    return buildByDistance(g, fillRow, options, grid);
  }
  // Resampled: each voxel's share of the bone, the mean of the label's indicator (1 inside, 0
  // out) at kLabelSubsamples^3 points over it, the indicator trilinear between stored voxels: a
  // nearest stored voxel's would rebuild their staircase, whose corners stand out up to half a
  // slice from the surface the stored voxels sample.
  using Sample = SampleOf<T>;
  const std::vector<Fill> fills = resampledFills(
      g, values, [&inside](T x) { return inside(x) ? Sample(1) : Sample(0); }, Sample(0),
      [](Sample share) {
        return Fill(std::lround(std::clamp(double(share), 0.0, 1.0) * kFillFull));
      },
      kLabelSubsamples);
  return buildByDistance(g, heldFills(fills), options, grid);
}

// A CT voxel of `hu`: its fill ramped around the iso level, its density from HU.
inline void ctVoxel(double hu, double iso, Fill& fill, Density& density) {
  fill = rampFill(hu, iso, kCtRampHalfWidthHu);
  density = fill == 0 ? 0 : hu >= kCorticalHu ? kCtCorticalDensity : kCtCancellousDensity;
}

// f of every value an 8 or 16-bit type holds (at most 65,536), indexed by its bits: placed
// exactly, rows look their voxels up instead of working each out.
template <typename T, typename F>
auto everyValueTable(F&& f) {
  using Bits = std::make_unsigned_t<T>;
  std::vector<decltype(f(T{}))> table(std::size_t(1) << (8 * sizeof(T)));
  for (std::size_t k = 0; k < table.size(); ++k) table[k] = f(T(Bits(k)));
  return table;
}

// A CT's grid: fill ramped around the iso level, density from HU. Returns the voxels inside.
template <typename T, typename Real>
std::uint64_t buildCt(const OutputGrid& g, StoredValues<T> values, const Real& real, double airHu,
                      double iso, VoxelGrid& grid) {
  if constexpr (std::is_integral_v<T> && sizeof(T) <= 2) {
    if (g.exact) {
      using Bits = std::make_unsigned_t<T>;
      const std::vector<std::pair<Fill, Density>> table = everyValueTable<T>([&](T v) {
        std::pair<Fill, Density> voxel;
        ctVoxel(real(v), iso, voxel.first, voxel.second);
        return voxel;
      });
      return buildGrid(grid,
                       [&](glm::ivec3 p, std::size_t i, int length, Fill* fill, Density* density) {
                         const std::size_t s = storedRow(g, p, i);
                         for (int x = 0; x < length; ++x) {
                           const auto& voxel = table[Bits(values[s + std::size_t(x)])];
                           fill[x] = voxel.first;
                           density[x] = voxel.second;
                         }
                       });
    }
  }
  if (g.exact) {
    return buildGrid(grid,
                     [&](glm::ivec3 p, std::size_t i, int length, Fill* fill, Density* density) {
                       const std::size_t s = storedRow(g, p, i);
                       for (int x = 0; x < length; ++x)
                         ctVoxel(real(values[s + std::size_t(x)]), iso, fill[x], density[x]);
                     });
  }
  // Resampled: bricks whose footprint's HU give one fill and density are set whole.
  using Sample = SampleOf<T>;
  const IndexMap m = indexMap(g);
  const auto value = [&real](T x) { return asSample<Sample>(real(x)); };
  const BrickRanges<Sample> ranges = brickRanges(g, m, values, value, asSample<Sample>(airHu), 0.0);
  const auto uniform = [&](glm::ivec3 b, Fill& fill, Density& density) {
    const auto [lo, hi] = ranges.of(b);
    const Sample margin = sampleMargin(lo, hi);
    Fill highFill = 0;
    Density highDensity = 0;
    ctVoxel(double(lo - margin), iso, fill, density);
    ctVoxel(double(hi + margin), iso, highFill, highDensity);
    return fill == highFill && density == highDensity;
  };
  return buildGridByBrick(
      grid, uniform, [&](glm::ivec3 p, std::size_t, int length, Fill* fill, Density* density) {
        Sample hu[kBrickEdge];
        trilinearRow(g, m, values, value, asSample<Sample>(airHu), p, length, hu);
        for (int x = 0; x < length; ++x) ctVoxel(double(hu[x]), iso, fill[x], density[x]);
      });
}

// A scalar volume's grid: fill ramped around the iso value, density by distance. Placed
// exactly, each fill is looked up (8 and 16-bit values) or computed twice rather than held (the
// load's memory stays that of a label map); resampled, the trilinear fills are held once.
template <typename T, typename Real>
std::uint64_t buildScalar(const OutputGrid& g, StoredValues<T> values, const Real& real,
                          double lowest, double iso, double halfWidth, const VolumeOptions& options,
                          VoxelGrid& grid) {
  if constexpr (std::is_integral_v<T> && sizeof(T) <= 2) {
    if (g.exact) {
      using Bits = std::make_unsigned_t<T>;
      const std::vector<Fill> table =
          everyValueTable<T>([&](T v) { return rampFill(real(v), iso, halfWidth); });
      const Fill* const fillOf = table.data();
      const auto fillRow = [&g, values, fillOf](glm::ivec3 p, std::size_t i, int length,
                                                Fill* out) {
        const std::size_t s = storedRow(g, p, i);
        for (int x = 0; x < length; ++x) out[x] = fillOf[Bits(values[s + std::size_t(x)])];
      };
      return buildByDistance(g, fillRow, options, grid);
    }
  }
  if (g.exact) {
    const auto fillRow = [&](glm::ivec3 p, std::size_t i, int length, Fill* out) {
      const std::size_t s = storedRow(g, p, i);
      for (int x = 0; x < length; ++x)
        out[x] = rampFill(real(values[s + std::size_t(x)]), iso, halfWidth);
    };
    return buildByDistance(g, fillRow, options, grid);
  }
  using Sample = SampleOf<T>;
  const std::vector<Fill> fills = resampledFills(
      g, values, [&real](T x) { return asSample<Sample>(real(x)); }, asSample<Sample>(lowest),
      [iso, halfWidth](Sample v) { return rampFill(double(v), iso, halfWidth); });
  return buildByDistance(g, heldFills(fills), options, grid);
}

}  // namespace osteon::geometry
