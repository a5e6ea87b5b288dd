// The header of osteon's own NRRD grids (its fill file and the density file beside it), read by
// nrrd_io.cpp's readNrrd through the shared NRRD header reader (nrrd_header.h).
#pragma once

#include <cstddef>
#include <fstream>
#include <string>

#include <glm/glm.hpp>

namespace osteon::geometry::nrrd {

enum class GridValue { Fill, Int16 };

struct GridHeader {
  glm::ivec3 sizes{0};
  bool bigEndian = false;
  double voxelSizeMm = 0.0;
  glm::dvec3 originMm{0.0};
  std::size_t valueBytes = 1;  // bytes per stored value
  std::string dataShown;       // the data's file, as messages name it
};

// Parses and checks the header of `path` (LPS, axis-aligned cubic voxels; osteon's keys must
// agree with the standard fields; the grid within +-1e9 mm); leaves `in` at the first data byte,
// wherever the header says the data lies. Throws InputError "<path>: <reason>".
GridHeader readGridHeader(const std::string& path, std::ifstream& in, GridValue expected,
                          bool allowOutsideData);

}  // namespace osteon::geometry::nrrd
