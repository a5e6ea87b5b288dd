#include "osteon/geometry/io/mesh_source.h"

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"

#include <cmath>
#include <sstream>

namespace osteon::geometry {

TriangleMesh loadMeshArgument(const std::string& argument, double scaleToMm,
                              MeshFileInfo* info) {
  if (argument != kDefaultModelArgument) return readMesh(argument, scaleToMm, info);
  if (!std::isfinite(scaleToMm) || scaleToMm <= 0.0) {
    std::ostringstream s;
    s << "--scale " << scaleToMm << ": must be a positive finite number";
    throw InputError(s.str());
  }
  TriangleMesh mesh = defaultHumerusModel().mesh;
  if (scaleToMm != 1.0) scaleInPlace(mesh, scaleToMm);
  checkScaledCoordinates(mesh, argument, scaleToMm);
  return mesh;
}

}  // namespace osteon::geometry
