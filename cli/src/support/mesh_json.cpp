#include "support/mesh_json.h"

#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/mesh_source.h"

namespace osteon::cli {

nlohmann::json meshJson(const std::string& argument, const simulation::BoneMesh& loaded) {
  const bool builtIn = argument == geometry::kDefaultModelArgument;
  nlohmann::json j = {{"path", argument},
                      {"built_in", builtIn},
                      {"scale_to_mm", loaded.read.scaleToMm},
                      {"vertices", loaded.mesh.vertexCount()},
                      {"triangles", loaded.mesh.triangleCount()}};
  if (!builtIn) {
    j["format"] = geometry::meshFormatName(loaded.read.meshFile.format);
    j["binary"] = loaded.read.meshFile.binary;
    j["polygons_triangulated"] = loaded.read.meshFile.polygonsTriangulated;
    j["degenerate_faces_dropped"] = loaded.read.meshFile.degenerateDropped;
  }
  return j;
}

}  // namespace osteon::cli
