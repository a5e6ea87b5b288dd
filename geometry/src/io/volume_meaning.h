// What a volume's values mean, kind by kind (volume_io.h; used by volume_load.cpp only): the
// values' summary, and the grid built from a label map, a CT or a scalar volume onto the
// OutputGrid (placed exactly or resampled).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "io/volume_grid_build.h"
#include "io/volume_sampling.h"
#include "osteon/core/error.h"
#include "osteon/core/number_text.h"
#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry {

// The range and, up to kMaxLabels + 1 of them, the distinct values and their counts (runs of
// equal values counted at once: volumes are mostly runs).
template <typename T>
struct ValueSummary {
  T lo{}, hi{};
  std::map<T, std::uint64_t> counts;
  bool many = false;  // more than kMaxLabels distinct values
};

template <typename T>
ValueSummary<T> summarise(StoredValues<T> values, std::size_t count) {
  ValueSummary<T> s;
  // The range in a pass of its own, which the compiler vectorises.
  T lo = values[0], hi = lo;
  for (std::size_t i = 0; i < count; ++i) {
    const T x = values[i];
    lo = x < lo ? x : lo;
    hi = x > hi ? x : hi;
  }
  s.lo = lo;
  s.hi = hi;
  // The distinct values, until there are too many to be labels (a scan: within a few voxels).
  T run = values[0];
  std::uint64_t runLength = 0;
  for (std::size_t i = 0; i < count && !s.many; ++i) {
    const T x = values[i];
    if (x == run) {
      ++runLength;
      continue;
    }
    s.counts[run] += runLength;
    s.many = s.counts.size() > std::size_t(kMaxLabels);
    run = x;
    runLength = 1;
  }
  if (!s.many) s.counts[run] += runLength;
  s.many = s.many || s.counts.size() > std::size_t(kMaxLabels);
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

inline glm::ivec3 positionOf(glm::ivec3 n, std::size_t i) {
  const std::size_t nx = std::size_t(n.x), ny = std::size_t(n.y);
  return {int(i % nx), int(i / nx % ny), int(i / (nx * ny))};
}

// Density by distance (label maps, scalar volumes): cortical within `shell` voxels of the
// outside or at the surface (fill below half), cancellous deeper.
inline Density distanceDensity(Fill fill, std::uint16_t distance, int shell) {
  if (fill == 0) return 0;
  return distance == 0 || distance <= shell ? kCtCorticalDensity : kCtCancellousDensity;
}

inline int shellVoxels(const VolumeOptions& options, const OutputGrid& g) {
  return int(std::clamp(std::ceil(options.corticalThicknessMm / g.voxelSizeMm), 1.0, 1e6));
}

// The grid of a fill per voxel (fillAt(position, index)), its density by the distance rule:
// cortical within the shell of voxels nearest the outside, cancellous deeper. Returns the voxels
// inside.
template <typename FillAt>
std::uint64_t buildByDistance(const OutputGrid& g, const FillAt& fillAt,
                              const VolumeOptions& options, VoxelGrid& grid) {
  // Whole (uncropped, exact) grids index the values by i alone: no position to work out.
  const std::vector<std::uint16_t> dist = insideDistance(g.sizes, [&](std::size_t i) {
    return fillAt(g.whole ? glm::ivec3(0) : positionOf(g.sizes, i), i) >= kFillHalf;
  });
  const int shell = shellVoxels(options, g);
  return buildGrid(grid, [&](glm::ivec3 p, std::size_t i, Fill& fill, Density& density) {
    fill = fillAt(p, i);
    density = distanceDensity(fill, dist[i], shell);
  });
}

// A label map's grid: each voxel 0 or full where placed exactly, its share inside where
// resampled; `inside` says which stored values are bone. Returns the voxels inside.
template <typename T, typename Inside>
std::uint64_t buildLabels(const OutputGrid& g, StoredValues<T> values, const Inside& inside,
                          const VolumeOptions& options, VoxelGrid& grid) {
  std::vector<Fill> fills;
  if (!g.exact) {
    fills.resize(g.count());
    for (std::size_t i = 0; i < fills.size(); ++i)
      fills[i] = labelFill(g, values, positionOf(g.sizes, i), i, inside);
  }
  const auto fillAt = [&](glm::ivec3 p, std::size_t i) {
    return g.exact ? labelFill(g, values, p, i, inside) : fills[i];
  };
  return buildByDistance(g, fillAt, options, grid);
}

// The fill of a value: 0 at iso - halfWidth, full at iso + halfWidth (a step when 0).
inline Fill rampFill(double value, double iso, double halfWidth) {
  if (!(halfWidth > 0.0)) return value >= iso ? kFillFull : Fill(0);
  const double t = (value - (iso - halfWidth)) / (2.0 * halfWidth);
  return Fill(std::lround(std::clamp(t, 0.0, 1.0) * kFillFull));
}

// A CT's grid: fill ramped around the iso level, density from HU. Returns the voxels inside.
template <typename T, typename Real>
std::uint64_t buildCt(const OutputGrid& g, StoredValues<T> values, const Real& real, double airHu,
                      double iso, VoxelGrid& grid) {
  return buildGrid(grid, [&](glm::ivec3 p, std::size_t i, Fill& fill, Density& density) {
    const double hu = sampleValue(g, values, p, i, real, airHu);
    fill = rampFill(hu, iso, kCtRampHalfWidthHu);
    density = fill == 0 ? 0 : hu >= kCorticalHu ? kCtCorticalDensity : kCtCancellousDensity;
  });
}

// A scalar volume's grid: fill ramped around the iso value, density by distance. Placed
// exactly, each fill is computed twice rather than held (the load's memory stays that of a label
// map); resampled, the trilinear fills are held once.
template <typename T, typename Real>
std::uint64_t buildScalar(const OutputGrid& g, StoredValues<T> values, const Real& real,
                          double lowest, double iso, double halfWidth, const VolumeOptions& options,
                          VoxelGrid& grid) {
  std::vector<Fill> fills;
  if (!g.exact) {
    fills.resize(g.count());
    for (std::size_t i = 0; i < fills.size(); ++i) {
      fills[i] =
          rampFill(trilinearValue(g, values, positionOf(g.sizes, i), real, lowest), iso, halfWidth);
    }
  }
  const auto fillAt = [&](glm::ivec3 p, std::size_t i) {
    return g.exact ? rampFill(sampleValue(g, values, p, i, real, lowest), iso, halfWidth)
                   : fills[i];
  };
  return buildByDistance(g, fillAt, options, grid);
}

}  // namespace osteon::geometry
