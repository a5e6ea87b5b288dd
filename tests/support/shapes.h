// Analytic test shapes as closed, outward triangle meshes (file helpers: files.h).
#pragma once

#include <string>

#include "osteon/geometry/io/mesh.h"

namespace osteon::test {

// UV sphere: `slices` around z, `stacks` from pole to pole.
geometry::TriangleMesh makeSphere(double radiusMm, int slices, int stacks,
                                  glm::dvec3 centreMm = glm::dvec3(0.0));
// Axis-aligned box from minMm to maxMm, 12 triangles.
geometry::TriangleMesh makeBox(glm::dvec3 minMm, glm::dvec3 maxMm);
// Torus around z: major radius R (centre to tube centre), minor radius r.
geometry::TriangleMesh makeTorus(double majorMm, double minorMm, int majorSegments,
                                 int minorSegments);

}  // namespace osteon::test
