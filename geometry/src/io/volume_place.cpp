// Placing a reader's volume in LPS (volume_place.h): exactly when its voxels are axis-aligned
// cubes, else marked for loadVolume's resampling, with the affine as read kept for the report.
#include "io/volume_place.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/number_text.h"
#include "osteon/geometry/io/mesh_io.h"

namespace osteon::geometry {

namespace {

std::string vectorText(double x, double y, double z) {
  return "(" + numberText(x) + ", " + numberText(y) + ", " + numberText(z) + ")";
}

// NaN or infinite voxels are refused wherever they are, before anything reads them as numbers
// (a NaN compares false with every threshold and would read as air); positions are the file's
// voxel indices (i fastest), as other tools show them.
template <typename T>
void refuseNonFinite(const std::string& path, const RawVolume& v, StoredValues<T> values) {
  if constexpr (std::is_floating_point_v<T>) {
    const std::size_t nx = std::size_t(v.sizes.x), ny = std::size_t(v.sizes.y);
    const std::size_t count = nx * ny * std::size_t(v.sizes.z);
    std::size_t bad = 0, first = 0;
    for (std::size_t i = 0; i < count; ++i) {
      if (!std::isfinite(values[i])) {
        if (bad++ == 0) first = i;
      }
    }
    if (bad == 0) return;
    const T firstValue = values[first];
    throw InputError(path + ": " + std::to_string(bad) + " of " + std::to_string(count) +
                     " voxels " + (bad == 1 ? "is" : "are") + " not a finite number (" + v.type +
                     " NaN or infinite), the first (" +
                     (std::isnan(firstValue) ? "NaN"
                      : firstValue > 0       ? "+Inf"
                                             : "-Inf") +
                     ") at voxel (" + std::to_string(first % nx) + ", " +
                     std::to_string(first / nx % ny) + ", " + std::to_string(first / (nx * ny)) +
                     ")");
  }
}

// The affine's numbers: finite, each axis's spacing from 1 nm (below it no scanner samples;
// such a spacing is a corrupt header).
void checkAffine(const std::string& path, const double m[3][3], glm::dvec3 centre0) {
  if (!(std::isfinite(centre0.x) && std::isfinite(centre0.y) && std::isfinite(centre0.z))) {
    throw InputError(path + ": the origin " + vectorText(centre0.x, centre0.y, centre0.z) +
                     " is not finite");
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!(std::isfinite(m[0][axis]) && std::isfinite(m[1][axis]) && std::isfinite(m[2][axis]))) {
      throw InputError(path + ": the direction of axis " + std::to_string(axis) + " " +
                       vectorText(m[0][axis], m[1][axis], m[2][axis]) + " is not finite");
    }
    const double scale =
        std::max({std::abs(m[0][axis]), std::abs(m[1][axis]), std::abs(m[2][axis])});
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      throw InputError(path + ": the voxel spacing of axis " + std::to_string(axis) + " is " +
                       (std::isfinite(scale) ? "zero" : "not a finite number"));
    }
    if (scale < 1e-6) {
      throw InputError(path + ": the voxel spacing of axis " + std::to_string(axis) + " is " +
                       numberText(scale) + " mm, below 1 nm");
    }
  }
}

// How each stored axis runs in LPS when the matrix is a scaled, signed permutation.
struct Alignment {
  bool aligned = true;     // every axis along one LPS axis
  bool cubic = true;       // and every spacing the same
  int row[3] = {0, 1, 2};  // the LPS axis each stored axis runs along
  bool flip[3] = {false, false, false};
  double spacing[3] = {1.0, 1.0, 1.0};  // each column's length
  double scale[3] = {1.0, 1.0, 1.0};    // each column's largest component (exact placement's)
};

Alignment alignmentOf(const std::string& path, const double m[3][3]) {
  Alignment a;
  for (int axis = 0; axis < 3; ++axis) {
    const double scale =
        std::max({std::abs(m[0][axis]), std::abs(m[1][axis]), std::abs(m[2][axis])});
    a.scale[axis] = scale;
    a.row[axis] = std::abs(m[0][axis]) == scale ? 0 : std::abs(m[1][axis]) == scale ? 1 : 2;
    for (int r = 0; r < 3; ++r) {
      if (r != a.row[axis] && std::abs(m[r][axis]) > 1e-6 * scale) a.aligned = false;
    }
    a.spacing[axis] =
        std::sqrt(m[0][axis] * m[0][axis] + m[1][axis] * m[1][axis] + m[2][axis] * m[2][axis]);
    a.flip[axis] = m[a.row[axis]][axis] < 0.0;
  }
  if (a.aligned) {
    for (int axis = 1; axis < 3; ++axis) {
      for (int other = 0; other < axis; ++other) {
        if (a.row[other] == a.row[axis]) {
          throw InputError(path + ": space directions of axes " + std::to_string(other) + " and " +
                           std::to_string(axis) + " both run along " + "LPS"[a.row[axis]] +
                           " (a degenerate direction matrix)");
        }
      }
    }
  } else {
    // Columns nearly parallel: no volume, only a corrupt header.
    const glm::dvec3 c0(m[0][0], m[1][0], m[2][0]), c1(m[0][1], m[1][1], m[2][1]),
        c2(m[0][2], m[1][2], m[2][2]);
    const double det = glm::dot(c0, glm::cross(c1, c2));
    if (!(std::abs(det) > 1e-6 * a.spacing[0] * a.spacing[1] * a.spacing[2])) {
      throw InputError(path + ": space directions " + vectorText(c0.x, c0.y, c0.z) + " " +
                       vectorText(c1.x, c1.y, c1.z) + " " + vectorText(c2.x, c2.y, c2.z) +
                       " are degenerate (they span no volume)");
    }
  }
  for (int axis = 1; axis < 3; ++axis) {
    if (std::abs(a.scale[axis] - a.scale[0]) > 1e-6 * a.scale[0]) a.cubic = false;
  }
  return a;
}

// Stored voxel (i, j, k) goes to placed index p[row[a]] = i_a (or its mirror), in one copy.
void reorder(const Alignment& al, glm::ivec3 stored, glm::ivec3 placed, RawVolume& v) {
  const std::size_t bytes = v.scalarBytes;
  std::vector<unsigned char> out(v.data.size());
  std::ptrdiff_t step[3];  // placed offset of one step along each stored axis
  std::ptrdiff_t start = 0;
  const std::ptrdiff_t placedStride[3] = {1, std::ptrdiff_t(placed.x),
                                          std::ptrdiff_t(placed.x) * std::ptrdiff_t(placed.y)};
  for (int a = 0; a < 3; ++a) {
    step[a] = placedStride[al.row[a]];
    if (al.flip[a]) {
      start += std::ptrdiff_t(stored[a] - 1) * step[a];
      step[a] = -step[a];
    }
  }
  std::size_t from = 0;
  for (int k = 0; k < stored.z; ++k) {
    for (int j = 0; j < stored.y; ++j) {
      std::ptrdiff_t to = start + k * step[2] + j * step[1];
      for (int i = 0; i < stored.x; ++i, ++from, to += step[0]) {
        std::memcpy(&out[std::size_t(to) * bytes], &v.data[from * bytes], bytes);
      }
    }
  }
  v.data.swap(out);
}

// Cubic axis-aligned voxels: the grid as stored, axes reordered and flipped into LPS.
void placeExactly(const std::string& path, const Alignment& al, glm::dvec3 centre0, RawVolume& v) {
  v.voxelSizeMm = (al.scale[0] + al.scale[1] + al.scale[2]) / 3.0;
  const glm::ivec3 stored = v.sizes;
  glm::ivec3 placed;
  glm::dvec3 lowCentre;
  for (int a = 0; a < 3; ++a) {
    placed[al.row[a]] = stored[a];
    lowCentre[al.row[a]] = al.flip[a] ? centre0[al.row[a]] - double(stored[a] - 1) * v.voxelSizeMm
                                      : centre0[al.row[a]];
  }
  v.sizes = placed;
  v.originMm = lowCentre - 0.5 * v.voxelSizeMm;
  for (int a = 0; a < 3; ++a) {
    if (!(std::abs(v.originMm[a]) <= kMaxCoordinateMm) ||
        !(std::abs(v.originMm[a] + v.sizes[a] * v.voxelSizeMm) <= kMaxCoordinateMm)) {
      throw InputError(path + ": voxel size " + numberText(v.voxelSizeMm) +
                       " mm puts the volume at " +
                       numberText(v.originMm[a] + v.sizes[a] * v.voxelSizeMm) + " mm on axis " +
                       std::to_string(a) + ", beyond +-1e9 mm (1000 km)");
    }
  }
  const bool identity = !al.flip[0] && !al.flip[1] && !al.flip[2] && al.row[0] == 0 &&
                        al.row[1] == 1 && al.row[2] == 2;
  if (!identity) reorder(al, stored, placed, v);
}

}  // namespace

void setVolumeValues(const nrrd::Scalar& scalar, bool bigEndian, std::vector<unsigned char>&& bytes,
                     std::size_t count, RawVolume& v) {
  bytes.resize(count * scalar.bytes);
  if (bigEndian && scalar.bytes > 1) {
    for (std::size_t i = 0; i < count; ++i)
      std::reverse(bytes.begin() + std::ptrdiff_t(i * scalar.bytes),
                   bytes.begin() + std::ptrdiff_t((i + 1) * scalar.bytes));
  }
  v.data = std::move(bytes);
  v.type = scalar.name;
  v.scalarBytes = scalar.bytes;
}

void refuseOverVolumeMemory(const std::string& path, glm::ivec3 sizes, std::size_t scalarBytes) {
  refuseOverMemory(
      path + ": a " + std::to_string(sizes.x) + " x " + std::to_string(sizes.y) + " x " +
          std::to_string(sizes.z) + " volume",
      volumeLoadMemoryBytes(sizes, scalarBytes),
      "crop or downsample it (fewer voxels) before loading, or use a machine with more memory");
}

glm::ivec3 checkVolumeSizes(const std::string& path, const std::vector<double>& s) {
  std::uint64_t voxels = 1;
  glm::ivec3 n;
  for (int a = 0; a < 3; ++a) {
    if (!(s[std::size_t(a)] >= 1 && s[std::size_t(a)] <= double(1 << 30) &&
          s[std::size_t(a)] == std::floor(s[std::size_t(a)]))) {
      throw InputError(path + ": sizes are not three integers from 1 to 2^30");
    }
    n[a] = int(s[std::size_t(a)]);
    voxels *= std::uint64_t(n[a]);
    if (voxels > VoxelGrid::kMaxVoxels) throw InputError(path + ": sizes exceed 2^32 voxels");
  }
  return n;
}

void placeVolume(const std::string& path, const double m[3][3], glm::dvec3 centre0, RawVolume& v) {
  v.visit([&](auto values) { refuseNonFinite(path, v, values); });
  checkAffine(path, m, centre0);
  const Alignment al = alignmentOf(path, m);
  for (int axis = 0; axis < 3; ++axis) {
    for (int r = 0; r < 3; ++r) v.indexToLpsMm[axis][r] = m[r][axis];
  }
  v.firstCentreMm = centre0;
  v.storedSizes = v.sizes;
  if (al.aligned && al.cubic) {
    v.resample = false;
    placeExactly(path, al, centre0, v);
    return;
  }
  // Anisotropic or oblique: the values stay as stored; loadVolume resamples them. The corners
  // of the stored box must lie within +-1e9 mm as an exact grid's must.
  v.resample = true;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 index((corner & 1) ? v.sizes.x - 0.5 : -0.5,
                           (corner & 2) ? v.sizes.y - 0.5 : -0.5,
                           (corner & 4) ? v.sizes.z - 0.5 : -0.5);
    const glm::dvec3 p = centre0 + v.indexToLpsMm * index;
    for (int a = 0; a < 3; ++a) {
      if (!(std::abs(p[a]) <= kMaxCoordinateMm)) {
        throw InputError(path + ": its spacing puts the volume at " + numberText(p[a]) +
                         " mm on axis " + std::to_string(a) + ", beyond +-1e9 mm (1000 km)");
      }
    }
  }
  v.voxelSizeMm = std::min({al.spacing[0], al.spacing[1], al.spacing[2]});
}

}  // namespace osteon::geometry
