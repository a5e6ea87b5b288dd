// The built-in bone: a procedural right proximal humerus in millimetres, written by our own
// code so the repository ships no downloaded data. `default` in place of a mesh path means
// this model; data/humerus_proximal.stl is the same mesh on disk (`osteon model` rewrites it).
//
// Frame: LPS as in DICOM, ITK and 3D Slicer (+x patient left, +y posterior, +z superior).
// For a right humerus medial is +x, lateral -x, anterior -y. The shaft axis is the z axis,
// pointing proximally; the head faces medially, superiorly and (retroversion) posteriorly.
#pragma once

#include <glm/vec3.hpp>

#include "osteon/geometry/io/mesh.h"

namespace osteon::geometry {

struct HumerusModelParams {
  double headDiameterMm = 46.0;      // articular sphere diameter
  double neckShaftAngleDeg = 135.0;  // between the head axis and the distal shaft axis
  double retroversionDeg = 25.0;     // head axis turned from medial towards posterior
  double shaftDiameterMm = 25.0;     // proximal diaphysis
  double shaftLengthMm = 100.0;      // from the surgical neck down to the distal cut
  double tessellationMm = 1.6;       // target edge length of the output mesh
};

struct HumerusModel {
  TriangleMesh mesh;                    // closed, 2-manifold, outward CCW, genus 0
  glm::dvec3 headCentreMm{0.0};         // centre of the articular sphere
  double headRadiusMm = 0.0;            // radius of the articular sphere
  glm::dvec3 headAxis{0.0};             // unit; from the head centre through the articular pole
  glm::dvec3 shaftAxis{0.0, 0.0, 1.0};  // unit; along the shaft, pointing proximally
};

// Deterministic: the same parameters give the same mesh bit for bit.
HumerusModel buildHumerusModel(const HumerusModelParams& params = {});

// The model of the default parameters, built at compile time into the library (the same
// bits as buildHumerusModel()): what `default` means, ready without running the build.
const HumerusModel& defaultHumerusModel();

}  // namespace osteon::geometry
