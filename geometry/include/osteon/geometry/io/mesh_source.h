// A mesh argument as commands take it: a file path, or `default` for the built-in humerus.
#pragma once

#include <string>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/io/mesh_io.h"

namespace osteon::geometry {

inline constexpr const char* kDefaultModelArgument = "default";

// `default` builds the procedural proximal humerus (millimetres) and then applies
// scaleToMm like any file; anything else is read with readMesh. info is filled for files.
TriangleMesh loadMeshArgument(const std::string& argument, double scaleToMm = 1.0,
                              MeshFileInfo* info = nullptr);

}  // namespace osteon::geometry
