// Volumes as users have them: NRRD (attached or detached header, raw or gzip, any scalar
// type) and NIfTI-1 (.nii, .nii.gz), turned into osteon's voxel grid with their meaning said,
// never guessed silently:
//   - osteon's own grids (NRRD with the content line and every key osteon writes) load as
//     readNrrd reads them; one stray osteon_* key does not make a user's volume a grid;
//   - a label map (integer type, at most kMaxLabels distinct values): the bone is one label
//     (VolumeOptions::label) or every non-zero voxel; each voxel is 0 or full;
//   - a CT (signed integer or floating type, values spanning at least kMinCtRangeHu): fill
//     ramps linearly from 0 at iso - kCtRampHalfWidthHu to full at iso + kCtRampHalfWidthHu,
//     so the surface (half full) sits at the iso HU; density comes from HU: cortical at or
//     above kCorticalHu, cancellous below (any voxel with fill > 0);
//   - anything else is an InputError naming the file and what was found (type, range,
//     distinct values).
// Space is LPS in mm; NIfTI's RAS is turned to LPS. Axes that run backwards (a negative
// direction) are flipped on loading; rotated (non-axis-aligned) or anisotropic grids are
// refused with a clear message.
#pragma once

#include "osteon/geometry/voxels/voxel_grid.h"

#include <optional>
#include <string>
#include <vector>

namespace osteon::geometry {

inline constexpr int kMaxLabels = 64;               // more distinct values: not a label map
inline constexpr double kMinCtRangeHu = 1000.0;     // a CT spans at least this much
inline constexpr double kDefaultIsoHu = 300.0;      // bone threshold by default
inline constexpr double kCtRampHalfWidthHu = 100.0; // fill 0 at iso-100 HU, full at iso+100 HU
inline constexpr double kCorticalHu = 800.0;        // cortical at or above, cancellous below
inline constexpr Density kCtCorticalDensity = 40;   // as the mesh voxelizer's defaults
inline constexpr Density kCtCancellousDensity = 15;

// True for paths osteon reads as a volume: .nrrd, .nhdr, .nii, .nii.gz (any case).
bool isVolumePath(const std::string& path);

struct VolumeOptions {
  std::optional<long long> label;  // label maps: the bone label (default: every non-zero)
  std::optional<double> isoHu;     // CTs: the bone threshold (default kDefaultIsoHu)
  double corticalThicknessMm = 2.0;  // label maps: voxels this close to outside are cortical
  bool allowOutsideData = false;   // NRRD: a `data file:` may lie outside the header's folder
};

struct VolumeLoad {
  VoxelGrid grid;
  std::string kind;                 // "osteon grid", "label map" or "ct"
  std::string format;               // "nrrd" or "nifti"
  std::string type;                 // the stored scalar type ("uint8", "int16", ...)
  double minValue = 0.0, maxValue = 0.0;
  std::vector<long long> labels;    // label maps: the distinct values found
  std::optional<long long> label;   // label maps: the label used (none: every non-zero)
  double isoHu = kDefaultIsoHu;     // CTs: the threshold used
  bool densityLoaded = false;       // osteon grids: a density file was read
};

// NRRD headers are read once for all (src/io/nrrd_header.h): a field given twice, a
// non-spatial kind (colour, vector, list) or a `data file:` outside the header's folder
// (unless allowOutsideData) is refused; `line skip:` and `byte skip:` are honoured.
// Throws InputError "<file>: <reason>" for anything it cannot honour.
VolumeLoad loadVolume(const std::string& path, const VolumeOptions& options = {});

// The raw scalars of a volume, x fastest then y then z, in LPS with positive axes (for tests
// and tools). voxelSizeMm is the (isotropic) edge, originMm the corner of voxel (0,0,0).
struct RawVolume {
  glm::ivec3 sizes{0};
  double voxelSizeMm = 1.0;
  glm::dvec3 originMm{0.0};
  std::string type;
  bool integer = true;
  bool isSigned = false;
  std::vector<double> values;
  bool osteonGrid = false;  // osteon's own NRRD grid: loadVolume hands it to readNrrd
};
RawVolume readRawVolume(const std::string& path, bool allowOutsideData = false);

}  // namespace osteon::geometry
