// Exact checks of a triangle surface (docs/validation.md, "The exact checks"): the crack-free
// guarantees as numbers. Combinatorial facts (borders, non-manifold elements, components, Euler
// characteristic) come from osteon's own topology pass; geometric ones (self-intersection,
// outward orientation, Hausdorff distance) from CGAL with exact predicates, kept in this one
// translation unit (CGAL is slow to compile and spreads its flags).
#pragma once

#include <cstddef>

#include "osteon/geometry/io/mesh.h"

namespace osteon::validation {

// Pairs of triangles that intersect other than through the vertices or edge they share
// (CGAL PMP::self_intersections on a polygon mesh; an exact pairwise test with a box broad
// phase on soups that are not one), counting at most `cap`. A degenerate triangle counts as a
// pair, as CGAL counts it.
std::size_t selfIntersectingPairs(const geometry::TriangleMesh& mesh, std::size_t cap = 100);
bool doesSelfIntersect(const geometry::TriangleMesh& mesh);

struct MeshReport {
  geometry::MeshTopology topology;
  std::size_t selfIntersections = 0;  // pairs, at most the cap
  bool selfIntersectionsCapped = false;
  bool outwardOriented = false;  // CGAL, on closed self-intersection-free meshes only
  double volumeMm3 = 0.0;        // signed; positive for an outward closed surface
  long long genus = -1;          // closed, manifold, one component; else -1
  // The winding numbers of the regions the surface bounds (outside is 0): a solid has 0 and 1
  // only. Two nested shells facing the same way give 2 inside the inner one; an inward shell
  // inside nothing gives -1. CGAL's volume components on closed self-intersection-free
  // polygon meshes; left 0..1 where that cannot be decided.
  int windingNumberMin = 0, windingNumberMax = 1;
  // Closed yet enclosing no volume (|volume| below 1e-9 of area^1.5): a sheet with both sides.
  bool flat = false;

  bool watertight() const { return topology.closed() && topology.manifold(); }
  // The crack-free guarantees: closed, manifold, consistently oriented outward, no
  // self-intersection, no degenerate face.
  bool passes() const {
    return watertight() && topology.consistentlyOriented() && selfIntersections == 0 &&
           topology.degenerateTriangles == 0 && outwardOriented && windingNumberMin >= 0 &&
           windingNumberMax <= 1 && !flat;
  }
};

MeshReport checkMesh(const geometry::TriangleMesh& mesh, std::size_t intersectionCap = 1000);

// Accuracy of `surface` against the mesh it came from.
struct Accuracy {
  double hausdorffMm = 0.0;           // two-sided: max of the two directed distances
  double surfaceToReferenceMm = 0.0;  // directed, from points on `surface`
  double referenceToSurfaceMm = 0.0;
  double volumeDifferenceMm3 = 0.0;  // surface - reference
  double volumeDifferencePercent = 0.0;
};

// CGAL's approximate Hausdorff distance (points sampled at `pointsPerMm2`, exact distances to
// an AABB tree of the other mesh). Throws std::invalid_argument unless both are polygon meshes.
Accuracy compareMeshes(const geometry::TriangleMesh& surface,
                       const geometry::TriangleMesh& reference, double pointsPerMm2 = 4.0);

}  // namespace osteon::validation
