#include "osteon/geometry/io/mesh_source.h"

#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/units.h"

namespace osteon::geometry {

TriangleMesh loadMeshArgument(const std::string& argument, double scaleToMm, MeshFileInfo* info) {
  if (argument != kDefaultModelArgument) return readMesh(argument, scaleToMm, info);
  resolveScaleToMm("mm", scaleToMm);
  TriangleMesh mesh = defaultHumerusModel().mesh;
  if (scaleToMm != 1.0) scaleInPlace(mesh, scaleToMm);
  checkScaledCoordinates(mesh, argument, scaleToMm);
  return mesh;
}

}  // namespace osteon::geometry
