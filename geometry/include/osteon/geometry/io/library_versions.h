// The versions of the libraries the geometry module is built with (Embree, OpenMesh, oneTBB,
// GLM), for reports that must say what produced their numbers. oneTBB's is the runtime
// library's own; the others, header-only or versioned with their headers, come from the
// headers compiled in.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace osteon::geometry {

using LibraryVersions = std::vector<std::pair<std::string, std::string>>;  // name, version

LibraryVersions libraryVersions();

}  // namespace osteon::geometry
