#include "io/volume_readers.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace osteon::geometry::io {

namespace {

bool endsWithLower(std::string path, const char* tail) {
  std::transform(path.begin(), path.end(), path.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  const std::string t = tail;
  return path.size() >= t.size() && path.compare(path.size() - t.size(), t.size(), t) == 0;
}

}  // namespace

bool isMetaImagePath(const std::string& path) {
  return endsWithLower(path, ".mha") || endsWithLower(path, ".mhd");
}

bool isDicomPath(const std::string& path) {
  if (endsWithLower(path, ".dcm") || endsWithLower(path, ".dicom") || endsWithLower(path, ".ima"))
    return true;
  // A folder is a DICOM series, unless its name is a mesh file's: then the mesh reader says
  // that it is a folder.
  for (const char* mesh : {".stl", ".obj", ".ply", ".off"}) {
    if (endsWithLower(path, mesh)) return false;
  }
  std::error_code ec;
  return std::filesystem::is_directory(path, ec);
}

}  // namespace osteon::geometry::io
