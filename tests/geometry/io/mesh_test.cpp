#include "osteon/geometry/io/mesh.h"

#include <cmath>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/units.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Mesh, BoxVolumeAreaBoundsAndTopology) {
  const TriangleMesh box = test::makeBox({-1, -2, -3}, {3, 2, 1});
  EXPECT_DOUBLE_EQ(signedVolumeMm3(box), 4.0 * 4.0 * 4.0);
  EXPECT_DOUBLE_EQ(surfaceAreaMm2(box), 6 * 16.0);
  const Aabb b = bounds(box);
  EXPECT_EQ(b.minMm, glm::dvec3(-1, -2, -3));
  EXPECT_EQ(b.maxMm, glm::dvec3(3, 2, 1));
  const MeshTopology t = analyzeTopology(box);
  EXPECT_TRUE(t.closed());
  EXPECT_TRUE(t.consistentlyOriented());
  EXPECT_EQ(t.edges, 18u);
  EXPECT_EQ(t.eulerCharacteristic, 2);
  EXPECT_EQ(t.components, 1u);
}

TEST(Mesh, SphereAndTorusAreOutwardWithTheRightEulerCharacteristic) {
  const TriangleMesh sphere = test::makeSphere(10.0, 64, 32);
  EXPECT_NEAR(signedVolumeMm3(sphere), 4.0 / 3.0 * kPi * 1000.0, 0.01 * 4188.8);
  EXPECT_EQ(analyzeTopology(sphere).eulerCharacteristic, 2);
  EXPECT_TRUE(analyzeTopology(sphere).closed());

  const TriangleMesh torus = test::makeTorus(10.0, 3.0, 96, 48);
  EXPECT_NEAR(signedVolumeMm3(torus), 2.0 * kPi * kPi * 10.0 * 9.0, 0.01 * 1776.5);
  const MeshTopology t = analyzeTopology(torus);
  EXPECT_TRUE(t.closed());
  EXPECT_TRUE(t.consistentlyOriented());
  EXPECT_EQ(t.eulerCharacteristic, 0);
}

TEST(Mesh, TopologyFindsHolesFinsFlipsAndDegenerates) {
  TriangleMesh holed = test::makeBox({0, 0, 0}, {1, 1, 1});
  holed.triangles.pop_back();
  EXPECT_EQ(analyzeTopology(holed).borderEdges, 3u);

  TriangleMesh flipped = test::makeBox({0, 0, 0}, {1, 1, 1});
  std::swap(flipped.triangles[0].y, flipped.triangles[0].z);
  EXPECT_EQ(analyzeTopology(flipped).misorientedEdges, 3u);
  EXPECT_TRUE(analyzeTopology(flipped).closed());

  TriangleMesh fin = test::makeBox({0, 0, 0}, {1, 1, 1});
  fin.positionsMm.push_back({0.5, 0.5, 3.0});
  fin.triangles.push_back({0, 1, 8});  // a third face on edge 0-1
  EXPECT_EQ(analyzeTopology(fin).nonManifoldEdges, 1u);

  // Two boxes sharing only a corner vertex: closed edges, but a pinched vertex.
  TriangleMesh pinched = test::makeBox({0, 0, 0}, {1, 1, 1});
  const TriangleMesh corner = test::makeBox({1, 1, 1}, {2, 2, 2});
  for (glm::u32vec3 t : corner.triangles) {
    for (int c = 0; c < 3; ++c) t[c] = t[c] == 0 ? 7u : t[c] + 8u;  // its corner 0 is box 1's 7
    pinched.triangles.push_back(t);
  }
  pinched.positionsMm.insert(pinched.positionsMm.end(), corner.positionsMm.begin(),
                             corner.positionsMm.end());
  EXPECT_TRUE(analyzeTopology(pinched).closed());
  EXPECT_EQ(analyzeTopology(pinched).nonManifoldVertices, 1u);
  EXPECT_EQ(analyzeTopology(test::makeBox({0, 0, 0}, {1, 1, 1})).nonManifoldVertices, 0u);

  TriangleMesh degenerate = test::makeBox({0, 0, 0}, {1, 1, 1});
  degenerate.triangles.push_back({0, 0, 1});
  degenerate.positionsMm.push_back({0.5, 0.0, 0.0});
  degenerate.triangles.push_back({0, 1, 8});  // collinear: zero area
  EXPECT_EQ(analyzeTopology(degenerate).degenerateTriangles, 2u);

  TriangleMesh two = test::makeBox({0, 0, 0}, {1, 1, 1});
  const TriangleMesh other = test::makeBox({5, 5, 5}, {6, 6, 6});
  for (glm::u32vec3 t : other.triangles) two.triangles.push_back(t + 8u);
  two.positionsMm.insert(two.positionsMm.end(), other.positionsMm.begin(), other.positionsMm.end());
  EXPECT_EQ(analyzeTopology(two).components, 2u);
  EXPECT_EQ(analyzeTopology(two).eulerCharacteristic, 4);
}

TEST(Mesh, ScaleAndUnits) {
  TriangleMesh box = test::makeBox({0, 0, 0}, {1, 1, 1});
  scaleInPlace(box, millimetresPer(parseLengthUnit("m")));
  EXPECT_DOUBLE_EQ(signedVolumeMm3(box), 1e9);
  EXPECT_DOUBLE_EQ(millimetresPer(parseLengthUnit("in")), 25.4);
  EXPECT_DOUBLE_EQ(millimetresPer(parseLengthUnit("cm")), 10.0);
  EXPECT_DOUBLE_EQ(millimetresPer(parseLengthUnit("mm")), 1.0);
  EXPECT_THROW(parseLengthUnit("furlong"), InputError);
  EXPECT_THROW(parseLengthUnit("MM"), InputError);
}

}  // namespace
}  // namespace osteon::geometry
