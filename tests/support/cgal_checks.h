// Exact geometric checks for tests, through CGAL (exact predicates). CGAL is slow to compile
// and spreads its flags, so it lives in this one test-only translation unit.
#pragma once

#include "osteon/geometry/mesh.h"

#include <cstddef>

namespace osteon::test {

// Number of pairs of triangles that intersect other than through shared vertices or edges
// (CGAL PMP::self_intersections), counting at most `cap` pairs.
std::size_t selfIntersectingPairs(const geometry::TriangleMesh& mesh, std::size_t cap = 100);

// CGAL's PMP::does_self_intersect on the mesh as a polygon soup turned into a surface mesh.
bool doesSelfIntersect(const geometry::TriangleMesh& mesh);

}  // namespace osteon::test
