// Volumes as users have them: NRRD (attached or detached header, raw or gzip, any scalar type),
// NIfTI-1 (.nii, .nii.gz), MetaImage (.mha, .mhd) and DICOM CT series (a folder, or a .dcm file),
// turned into osteon's voxel grid with their meaning said, never
// guessed silently:
//   - osteon's own grids (NRRD with the content line and every key osteon writes) load as
//     readNrrd reads them; one stray osteon_* key does not make a user's volume a grid;
//   - a label map (an integer type, or a float type whose values are all whole, at most
//     kMaxLabels distinct values, none negative): the bone is one label (VolumeOptions::label)
//     or every voxel but the background, which is 0 when 0 is among the values, else the most
//     common value (ties: the lowest); each voxel is 0 or full. Labels stay in their integer
//     type (64-bit labels past 2^53 stay distinct). An all-zero volume is a label map of no bone;
//   - a CT (signed values spanning at least kMinCtRangeHu): fill ramps linearly from 0 at
//     iso - kCtRampHalfWidthHu to full at iso + kCtRampHalfWidthHu, so the surface (half full)
//     sits at the iso HU; density comes from HU: cortical at or above kCorticalHu, cancellous
//     below (any voxel with fill > 0). Negative values make a volume a CT or nothing unless an
//     iso level is given: labels are never negative, HU are;
//   - a scalar volume (any other type and range, given VolumeOptions::isoValue in its own units:
//     micro-CT, probability or partial-volume maps): bone lies above the iso value, the fill
//     ramped over kScalarRampHalfWidth of the value range either side; density by the distance
//     rule of label maps (cortical within corticalThicknessMm of the outside);
//   - anything else is an InputError naming the file and what was found (type, range,
//     distinct values). So are NaN or infinite voxels (their count and the first one's file
//     index), and a volume whose every voxel is bone (no surface to drill: not a bone).
// Space is LPS in mm; NIfTI's RAS is turned to LPS. Axis-aligned cubic voxels are placed
// exactly (axes that run backwards are flipped, axes stored in another order reordered);
// anisotropic or oblique voxels are resampled onto a cubic, axis-aligned LPS grid (trilinear for
// CTs and scalar volumes, partial-volume for label maps), at VolumeOptions::voxelSizeMm or the
// finest spacing. The transform is reported (VolumeLoad::transform). Library messages name the
// VolumeOptions fields ("volume.isoValue"), which front ends rename to their own terms.
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

inline constexpr int kMaxLabels = 64;                 // more distinct values: not a label map
inline constexpr double kMinCtRangeHu = 1000.0;       // a CT spans at least this much
inline constexpr double kDefaultIsoHu = 300.0;        // bone threshold by default
inline constexpr double kCtRampHalfWidthHu = 100.0;   // fill 0 at iso-100 HU, full at iso+100 HU
inline constexpr double kScalarRampHalfWidth = 0.05;  // scalar volumes: of the value range
inline constexpr double kCorticalHu = 800.0;          // cortical at or above, cancellous below
inline constexpr Density kCtCorticalDensity = 40;     // as the mesh voxelizer's defaults
inline constexpr Density kCtCancellousDensity = 15;

// True for paths osteon reads as a volume: .nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd, .dcm,
// .dicom, .ima (any case) and folders (DICOM series).
bool isVolumePath(const std::string& path);
// The format a volume path is read as: "nrrd", "nifti", "metaimage" or "dicom".
std::string volumeFormat(const std::string& path);

// An axis-aligned box in LPS mm: [minMm, maxMm] on each axis.
struct BoxMm {
  glm::dvec3 minMm{0.0}, maxMm{0.0};
};

struct VolumeOptions {
  std::optional<std::uint64_t>
      label;  // label maps: the bone label (default: all but the background)
  // CTs: the bone threshold in HU (default kDefaultIsoHu); any other volume: in its own units,
  // which makes it a scalar volume. Finite.
  std::optional<double> isoValue;
  double corticalThicknessMm = 2.0;  // label maps: voxels this close to outside are cortical
  bool allowOutsideData =
      false;           // NRRD, MetaImage: a data file may lie outside the header's folder
  std::string series;  // DICOM: the Series Instance UID to read (default: the most slices)
  // Resampled volumes (anisotropic or oblique): the cubic voxel's edge (default: the finest
  // spacing). Positive.
  std::optional<double> voxelSizeMm;
  // Only this box is loaded (LPS mm, voxels whose centres lie inside it); it must overlap the
  // volume.
  std::optional<BoxMm> cropMm;
  // Label maps: only the bounding box of this label, grown by cropMarginMm on every side.
  std::optional<std::uint64_t> cropToLabel;
  double cropMarginMm = 10.0;  // at least 0
};

// How the stored grid was turned into osteon's (reported with every volume).
struct VolumeTransform {
  glm::ivec3 storedSizes{0};      // as stored
  glm::dvec3 spacingMm{1.0};      // of each stored axis
  glm::dmat3 directions{1.0};     // columns: each stored axis's unit direction in LPS
  glm::dvec3 firstCentreMm{0.0};  // centre of stored voxel (0, 0, 0), LPS mm
  bool resampled = false;         // anisotropic or oblique: resampled (else placed exactly)
  std::string interpolation;      // "none", "trilinear" or "partial volume"
  bool cropped = false;           // cropMm or cropToLabel took part of the volume
};

struct VolumeLoad {
  VoxelGrid grid;
  std::string kind;                       // "osteon grid", "label map", "ct" or "scalar"
  std::string format;                     // as volumeFormat names it
  std::string type;                       // the stored scalar type ("uint8", "int16", ...)
  double minValue = 0.0, maxValue = 0.0;  // as numbers (label maps: exact in `labels`)
  std::vector<std::uint64_t> labels;      // label maps: the distinct values found, ascending
  std::optional<std::uint64_t> label;  // label maps: the label used (none: all but the background)
  std::uint64_t background = 0;        // label maps: 0 if present, else the most common value
  double isoValue = kDefaultIsoHu;     // CTs and scalar volumes: the threshold used
  double rampHalfWidth = kCtRampHalfWidthHu;  // CTs and scalar volumes: fill ramp either side
  bool densityLoaded = false;                 // osteon grids: a density file was read
  std::string seriesUid, seriesDescription;   // DICOM: the series read (its description may be "")
  VolumeTransform transform;                  // volumes (not osteon grids)
};

// NRRD headers are read once for all (src/io/nrrd_header.h): a field given twice, a
// non-spatial kind (colour, vector, list) or a `data file:` outside the header's folder
// (unless allowOutsideData) is refused; `line skip:` and `byte skip:` are honoured.
// Throws InputError "<file>: <reason>" for anything it cannot honour, and OptionError
// "volume.isoValue <value>: ..." (and so on) for an option that cannot be (not finite).
VolumeLoad loadVolume(const std::string& path, const VolumeOptions& options = {});

// An upper bound of the memory loadVolume needs (bytes) for a volume of these sizes stored as
// scalars of `scalarBytes`: its phases' per-voxel peak (a reordered copy of the values
// included) plus the two constants below. A larger volume is refused before it is read
// (tests/geometry/io/volume_memory_test.cpp measures the bound).
double volumeLoadMemoryBytes(glm::ivec3 sizes, std::size_t scalarBytes);
// osteon itself: code, libraries and thread stacks (about 70 MB of address space measured).
inline constexpr double kVolumeLoadProcessBytes = 128e6;
// Freed buffers glibc's allocator keeps: below its dynamic mmap threshold (at most 32 MiB) a
// buffer comes from the heap and may stay there once freed; a load frees at most four.
inline constexpr double kVolumeLoadHeapSlackBytes = 4.0 * 32 * 1024 * 1024;

// Stored values of type T read from bytes (memcpy: no aliasing of the byte buffer).
template <typename T>
struct StoredValues {
  using type = T;
  const unsigned char* bytes = nullptr;
  T operator[](std::size_t i) const {
    T v;
    std::memcpy(&v, bytes + i * sizeof(T), sizeof(T));
    return v;
  }
};

// The raw scalars of a volume, x fastest then y then z (for tests and tools). Placed exactly
// (resample false): in LPS with positive axes, voxelSizeMm the (isotropic) edge, originMm the
// corner of voxel (0,0,0). Else as stored, the affine below saying where, and voxelSizeMm the
// finest spacing.
// The values stay in their stored type (in the host's byte order): 64-bit integers stay exact,
// and a volume costs its stored bytes, not a double per voxel.
struct RawVolume {
  glm::ivec3 sizes{0};
  double voxelSizeMm = 1.0;
  glm::dvec3 originMm{0.0};
  std::string
      type;  // "int8" "uint8" "int16" "uint16" "int32" "uint32" "int64" "uint64" "float" "double"
  std::size_t scalarBytes = 1;
  bool integer = true;    // the values are the stored integers (an integer type, unscaled)
  bool isSigned = false;  // the values may be negative
  double slope = 1.0,
         intercept = 0.0;  // NIfTI scl_slope, scl_inter: value = stored * slope + intercept
  std::vector<unsigned char> data;  // sizes.x * sizes.y * sizes.z stored values
  bool osteonGrid = false;          // osteon's own NRRD grid: loadVolume hands it to readNrrd
  std::string seriesUid, seriesDescription;  // DICOM: the series read
  // The affine as read: stored voxel (i, j, k)'s centre lies at firstCentreMm + indexToLpsMm *
  // (i, j, k) (columns: one step along each stored axis, LPS mm).
  glm::dmat3 indexToLpsMm{1.0};
  glm::dvec3 firstCentreMm{0.0};
  glm::ivec3 storedSizes{0};
  bool resample = false;  // anisotropic or oblique: data as stored, to be resampled

  // Calls f(values) with `values` a StoredValues<T> of the stored type T.
  template <typename F>
  decltype(auto) visit(F&& f) const;
};
RawVolume readRawVolume(const std::string& path, bool allowOutsideData = false);
// Every format; options.allowOutsideData and options.series as above (the rest is meaning).
RawVolume readRawVolume(const std::string& path, const VolumeOptions& options);

template <typename F>
decltype(auto) RawVolume::visit(F&& f) const {
  const unsigned char* p = data.data();
  if (type == "int8") return f(StoredValues<std::int8_t>{p});
  if (type == "uint8") return f(StoredValues<std::uint8_t>{p});
  if (type == "int16") return f(StoredValues<std::int16_t>{p});
  if (type == "uint16") return f(StoredValues<std::uint16_t>{p});
  if (type == "int32") return f(StoredValues<std::int32_t>{p});
  if (type == "uint32") return f(StoredValues<std::uint32_t>{p});
  if (type == "int64") return f(StoredValues<std::int64_t>{p});
  if (type == "uint64") return f(StoredValues<std::uint64_t>{p});
  if (type == "float") return f(StoredValues<float>{p});
  return f(StoredValues<double>{p});
}

}  // namespace osteon::geometry
