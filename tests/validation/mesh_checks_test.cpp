#include "osteon/validation/mesh_checks.h"

#include <cmath>

#include <gtest/gtest.h>

#include "support/shapes.h"

namespace osteon::validation {
namespace {

using geometry::TriangleMesh;

TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const auto offset = std::uint32_t(a.positionsMm.size());
  m.positionsMm.insert(m.positionsMm.end(), b.positionsMm.begin(), b.positionsMm.end());
  for (const glm::u32vec3& t : b.triangles) m.triangles.push_back(t + offset);
  return m;
}

TEST(MeshChecks, AClosedSpherePassesWithItsVolumeAndGenus) {
  const TriangleMesh sphere = test::makeSphere(10.0, 64, 32);
  const MeshReport r = checkMesh(sphere);
  EXPECT_TRUE(r.passes());
  EXPECT_EQ(r.genus, 0);
  EXPECT_TRUE(r.outwardOriented);
  EXPECT_EQ(r.selfIntersections, 0u);
  EXPECT_NEAR(r.volumeMm3, 4.0 / 3.0 * M_PI * 1000.0, 0.01 * 4.0 / 3.0 * M_PI * 1000.0);
  EXPECT_EQ(checkMesh(test::makeTorus(10.0, 3.0, 48, 24)).genus, 1);
}

TEST(MeshChecks, AHoleAFlipAnOverlapAndAFinEachFail) {
  TriangleMesh holed = test::makeSphere(10.0, 32, 16);
  holed.triangles.pop_back();
  const MeshReport h = checkMesh(holed);
  EXPECT_FALSE(h.passes());
  EXPECT_EQ(h.topology.borderEdges, 3u);

  TriangleMesh flipped = test::makeSphere(10.0, 32, 16);
  for (glm::u32vec3& t : flipped.triangles) std::swap(t.y, t.z);
  const MeshReport f = checkMesh(flipped);
  EXPECT_TRUE(f.watertight());
  EXPECT_FALSE(f.outwardOriented);
  EXPECT_FALSE(f.passes());
  EXPECT_LT(f.volumeMm3, 0.0);

  const TriangleMesh overlap = merged(test::makeSphere(10.0, 32, 16),
                                      test::makeSphere(10.0, 32, 16, glm::dvec3(8.0, 0.0, 0.0)));
  const MeshReport o = checkMesh(overlap);
  EXPECT_TRUE(o.watertight());
  EXPECT_GT(o.selfIntersections, 10u);
  EXPECT_EQ(o.topology.components, 2u);
  EXPECT_FALSE(o.passes());
  const MeshReport capped = checkMesh(overlap, 5);
  EXPECT_EQ(capped.selfIntersections, 5u);
  EXPECT_TRUE(capped.selfIntersectionsCapped);

  TriangleMesh fin = test::makeBox({0, 0, 0}, {1, 1, 1});
  const glm::u32vec3 t0 = fin.triangles[0];
  fin.positionsMm.push_back({0.5, 0.5, 3.0});
  fin.triangles.push_back(
      {t0.x, t0.y, std::uint32_t(fin.positionsMm.size() - 1)});  // a third face on an edge
  const MeshReport n = checkMesh(fin);
  EXPECT_GT(n.topology.nonManifoldEdges, 0u);
  EXPECT_FALSE(n.passes());
}

TEST(MeshChecks, HausdorffAndVolumeAgainstTheReference) {
  const TriangleMesh fine = test::makeSphere(10.0, 128, 64);
  const Accuracy same = compareMeshes(test::makeSphere(10.0, 96, 48), fine);
  EXPECT_LT(same.hausdorffMm, 0.05);  // two tessellations of one sphere
  const Accuracy bigger = compareMeshes(test::makeSphere(11.0, 128, 64), fine);
  EXPECT_NEAR(bigger.hausdorffMm, 1.0, 0.02);
  EXPECT_NEAR(bigger.volumeDifferencePercent, 100.0 * (1.331 - 1.0), 1.0);
}

// The sample points are seeded: the same meshes give the same distance, run after run (a
// nightly report compared with yesterday's must not move by chance).
TEST(MeshChecks, HausdorffIsRepeatable) {
  const TriangleMesh coarse = test::makeSphere(10.0, 24, 12);
  const TriangleMesh fine = test::makeSphere(10.0, 128, 64);
  const Accuracy first = compareMeshes(coarse, fine);
  const Accuracy second = compareMeshes(coarse, fine);
  EXPECT_GT(first.hausdorffMm, 0.0);
  EXPECT_EQ(first.surfaceToReferenceMm, second.surfaceToReferenceMm);
  EXPECT_EQ(first.referenceToSurfaceMm, second.referenceToSurfaceMm);
}

}  // namespace
}  // namespace osteon::validation
