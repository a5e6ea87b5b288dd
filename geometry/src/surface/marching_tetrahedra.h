// A small private mesher for implicit surfaces: marching tetrahedra over a regular grid, then
// tangential relaxation back onto the zero set. Used by the built-in bone model.
#pragma once

#include <functional>

#include <glm/vec3.hpp>

#include "osteon/geometry/io/mesh.h"

namespace osteon::geometry::detail {

// f(p) < 0 inside, > 0 outside, in millimetres; ideally close to a signed distance.
using ImplicitFunction = std::function<double(const glm::dvec3&)>;

// Central-difference gradient of f with step stepMm.
glm::dvec3 implicitGradient(const ImplicitFunction& f, const glm::dvec3& pMm, double stepMm);

// Polygonises the zero set of f inside box (padded by two cells) at grid spacing spacingMm.
// Each cube is split into six tetrahedra around its main diagonal (Kuhn), the same in every
// cube, so shared faces are split alike and the result is closed and 2-manifold; the grid's
// outer layer counts as outside, so a surface leaving the box is cut off there, not left
// open. One vertex per crossed grid edge; triangles are outward counter-clockwise.
// Deterministic. Throws std::length_error past 2^32 grid points.
TriangleMesh marchingTetrahedra(const ImplicitFunction& f, const Aabb& box, double spacingMm);

// Improves triangle shapes without changing connectivity: each iteration moves every vertex
// part way to its neighbours' average within the tangent plane, then pulls it back onto the
// zero set with a few Newton steps.
void relaxOntoZeroSet(TriangleMesh& mesh, const ImplicitFunction& f, double spacingMm,
                      int iterations);

}  // namespace osteon::geometry::detail
