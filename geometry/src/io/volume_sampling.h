// Where loadVolume's grid lies and how each of its voxels samples the stored values
// (volume_sampling.cpp): exactly (a placed volume, cropped or not: voxel p is stored voxel
// p + offset) or resampled (anisotropic or oblique: the stored grid's affine inverted,
// volume_resample.h samples it).
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry {

struct OutputGrid {
  glm::ivec3 sizes{0};
  glm::dvec3 originMm{0.0};
  double voxelSizeMm = 1.0;
  bool exact = true;  // voxel p is stored voxel p + offset
  glm::ivec3 offset{0};
  glm::ivec3 stored{0};           // the stored (placed, when exact) sizes
  bool whole = true;              // exact and uncropped: voxel i is stored voxel i
  glm::dmat3 lpsToIndex{1.0};     // resampled: an LPS point's continuous stored index...
  glm::dvec3 firstCentreMm{0.0};  // ...measured from stored voxel (0, 0, 0)'s centre

  std::size_t count() const {
    return std::size_t(sizes.x) * std::size_t(sizes.y) * std::size_t(sizes.z);
  }
  std::size_t storedOffset(glm::ivec3 s) const {
    return (std::size_t(s.z) * std::size_t(stored.y) + std::size_t(s.y)) * std::size_t(stored.x) +
           std::size_t(s.x);
  }
  glm::dvec3 storedIndex(glm::dvec3 pointMm) const {
    return lpsToIndex * (pointMm - firstCentreMm);
  }
  glm::dvec3 centreMm(glm::ivec3 p) const { return originMm + (glm::dvec3(p) + 0.5) * voxelSizeMm; }
};

// The grid loadVolume builds: the stored one placed exactly, or the resampled one at
// options.voxelSizeMm (default: raw.voxelSizeMm, the finest spacing); either cut to `crop`
// (voxels whose centres lie inside it). Throws InputError for a crop outside the volume, an
// OptionError for a voxel size that is not positive, and refuses a resampled grid past memory.
OutputGrid planOutput(const std::string& path, const RawVolume& raw, const VolumeOptions& options,
                      const std::optional<BoxMm>& crop);

// LPS box of stored voxels [lo, hi] (inclusive indices), their full extent.
BoxMm storedBoxMm(const RawVolume& raw, glm::ivec3 lo, glm::ivec3 hi);

// Stored index bounds (inclusive) of the voxels where inside(value): none when lo > hi.
template <typename Values, typename Inside>
std::pair<glm::ivec3, glm::ivec3> insideBounds(glm::ivec3 n, const Values& values,
                                               const Inside& inside) {
  glm::ivec3 lo(n), hi(-1);
  std::size_t i = 0;
  for (int z = 0; z < n.z; ++z) {
    for (int y = 0; y < n.y; ++y) {
      for (int x = 0; x < n.x; ++x, ++i) {
        if (!inside(values[i])) continue;
        lo = glm::min(lo, glm::ivec3(x, y, z));
        hi = glm::max(hi, glm::ivec3(x, y, z));
      }
    }
  }
  return {lo, hi};
}

}  // namespace osteon::geometry
