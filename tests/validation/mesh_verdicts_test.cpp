// Surfaces that are closed and manifold yet no solid: a flat square with both sides (it used to
// be called "open: 0 border edges", or passed when its sides shared no diagonal) and two nested
// spheres facing the same way (winding number 2 inside the inner one; it passed).
#include <gtest/gtest.h>

#include "osteon/validation/mesh_checks.h"
#include "support/shapes.h"

namespace osteon::validation {
namespace {

geometry::TriangleMesh joined(const geometry::TriangleMesh& a, geometry::TriangleMesh b,
                              bool flipB) {
  geometry::TriangleMesh out = a;
  const auto offset = std::uint32_t(a.positionsMm.size());
  out.positionsMm.insert(out.positionsMm.end(), b.positionsMm.begin(), b.positionsMm.end());
  for (glm::u32vec3 t : b.triangles) {
    if (flipB) std::swap(t.y, t.z);
    out.triangles.push_back(t + offset);
  }
  return out;
}

TEST(MeshCheckVerdicts, NestedShellsFacingTheSameWayFailWithWindingNumberTwo) {
  const geometry::TriangleMesh outer = test::makeSphere(10.0, 24, 12);
  const geometry::TriangleMesh inner = test::makeSphere(5.0, 24, 12);
  const MeshReport nested = checkMesh(joined(outer, inner, false));
  EXPECT_TRUE(nested.watertight());
  EXPECT_EQ(nested.selfIntersections, 0u);
  EXPECT_TRUE(nested.outwardOriented);
  EXPECT_EQ(nested.windingNumberMax, 2);
  EXPECT_FALSE(nested.passes());
  // The inner shell turned inward is a hollow ball: a solid, 0 and 1 only.
  const MeshReport hollow = checkMesh(joined(outer, inner, true));
  EXPECT_EQ(hollow.windingNumberMin, 0);
  EXPECT_EQ(hollow.windingNumberMax, 1);
  EXPECT_TRUE(hollow.passes());
  // One sphere, and two apart, are solids too.
  EXPECT_TRUE(checkMesh(outer).passes());
  const MeshReport apart =
      checkMesh(joined(outer, test::makeSphere(5.0, 24, 12, glm::dvec3(30.0, 0.0, 0.0)), false));
  EXPECT_EQ(apart.windingNumberMax, 1);
  EXPECT_TRUE(apart.passes());
}

TEST(MeshCheckVerdicts, AFlatSquareWithBothSidesIsClosedButNoSolid) {
  geometry::TriangleMesh square;
  square.positionsMm = {{0, 0, 3}, {1, 0, 3}, {1, 1, 3}, {0, 1, 3}};
  // The back's diagonal crosses the front's: every edge has two triangles, no border.
  square.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
  const MeshReport r = checkMesh(square);
  EXPECT_EQ(r.topology.borderEdges, 0u);
  EXPECT_TRUE(r.topology.closed());
  EXPECT_TRUE(r.flat);
  EXPECT_FALSE(r.passes());
  // A closed solid is not flat.
  EXPECT_FALSE(checkMesh(test::makeBox({0, 0, 0}, {1, 1, 1})).flat);
}

}  // namespace
}  // namespace osteon::validation
