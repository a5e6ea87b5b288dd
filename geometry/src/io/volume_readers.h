// The volume readers beside NRRD and NIfTI (volume_io.cpp): MetaImage (metaimage_io.cpp) and
// DICOM (dicom_volume.cpp, through the libosteon_dicom.so plugin). Each returns its values as
// stored with the geometry the file gives; readRawVolume places them (LPS, axes reordered and
// flipped, or resampled) in the one step every volume goes through (volume_place.h).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "osteon/geometry/io/volume_io.h"

namespace osteon::geometry::io {

// A volume before placing: volume.sizes and volume.data in stored order (i fastest), values in
// the host's byte order; m's columns are each stored axis's step in LPS mm (direction times
// spacing), centre0 the centre of voxel (0,0,0) in LPS mm.
struct StoredVolume {
  RawVolume volume;
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  glm::dvec3 centre0{0.0};
};

// .mha, .mhd (any case).
bool isMetaImagePath(const std::string& path);
// A folder (read as a DICOM series), or .dcm, .dicom, .ima (any case), or a file named DICOMDIR's
// way without an extension is not guessed: only these.
bool isDicomPath(const std::string& path);

// MetaImage: attached (.mha, ElementDataFile = LOCAL) or detached (.mhd with a data file in the
// header's folder unless allowOutsideData); raw or zlib (CompressedData); any MET_ scalar.
StoredVolume readMetaImage(const std::string& path, bool allowOutsideData);

// A DICOM CT series: a folder (the series `seriesUid`, default the one with most slices) or one
// file (a multi-frame image, or one slice standing for its series in its folder).
StoredVolume readDicom(const std::string& path, const std::string& seriesUid);

}  // namespace osteon::geometry::io
