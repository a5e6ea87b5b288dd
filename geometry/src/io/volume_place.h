// The one way a reader's volume enters osteon (volume_place.cpp): every reader (NRRD, NIfTI,
// and any other) hands its decoded values with the grid's affine here, and gets back a RawVolume
// either placed exactly (axis-aligned cubic voxels: axes reordered and flipped into LPS, the
// values untouched) or marked for resampling (anisotropic or oblique voxels: loadVolume resamples
// it onto a cubic LPS grid once it knows what the values mean).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "io/nrrd_header.h"
#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry {

// m: the direction matrix in LPS, m[row][axis] (column `axis` is one step along stored axis
// `axis`, in mm, so its length is that axis's spacing); centre0: the centre of stored voxel
// (0, 0, 0) in LPS mm. v holds sizes and values (decoded, x fastest). Checks the values (NaN,
// infinite), the affine (finite, spacing from 1 nm, not degenerate) and that the volume lies
// within +-1e9 mm; throws InputError "<path>: <reason>".
void placeVolume(const std::string& path, const double m[3][3], glm::dvec3 centre0, RawVolume& v);

// Three sizes read as doubles: integers from 1 to 2^30, at most VoxelGrid::kMaxVoxels voxels.
glm::ivec3 checkVolumeSizes(const std::string& path, const std::vector<double>& sizes);

// Makes `bytes` (count values of `scalar` in the file's byte order) the volume's values, in the
// host's order (little-endian hosts only, as osteon's targets), in place: no second copy.
void setVolumeValues(const nrrd::Scalar& scalar, bool bigEndian, std::vector<unsigned char>&& bytes,
                     std::size_t count, RawVolume& v);

// NIfTI-1 (.nii, .nii.gz): nifti_volume.cpp.
RawVolume readNiftiVolume(const std::string& path);

// A volume past the machine's memory is refused before any of it is allocated.
void refuseOverVolumeMemory(const std::string& path, glm::ivec3 sizes, std::size_t scalarBytes);

}  // namespace osteon::geometry
