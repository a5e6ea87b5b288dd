#include "osteon/validation/crack_metric.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon::validation {
namespace {

TEST(CrackMetric, AClosedSphereShowsNoRedAndAHoleShowsRed) {
  const geometry::TriangleMesh sphere = test::makeSphere(10.0, 64, 32);
  const CrackMetric closed = measureCracks(sphere, {128, false});
  EXPECT_EQ(closed.red, 0u);
  // The sphere's disc fills pi/4 of the square (the view's margin aside) in each view.
  EXPECT_NEAR(double(closed.white) / (6.0 * 128 * 128), M_PI / 4 / (1.02 * 1.02), 0.02);
  geometry::TriangleMesh holed = sphere;
  holed.triangles.erase(holed.triangles.begin() + 1000, holed.triangles.begin() + 1040);
  const CrackMetric open = measureCracks(holed, {128, false});
  EXPECT_GT(open.red, 0u);
  EXPECT_GT(open.crackPercent(), 0.0);
  geometry::TriangleMesh flipped = sphere;
  for (glm::u32vec3& t : flipped.triangles) std::swap(t.y, t.z);
  EXPECT_EQ(measureCracks(flipped, {64, false}).white, 0u);  // every face seen from behind
  EXPECT_THROW(measureCracks(sphere, {8, false}), InputError);
}

// The seed's comparison, measured: the naive marching cubes surface of the built-in humerus
// shows cracks, the crack-free one none, on the same voxels.
TEST(CrackMetric, NaiveMarchingCubesCracksAndCrackFreeDoesNot) {
  geometry::VoxelizeOptions vo;
  vo.voxelSizeMm = 1.2;
  const geometry::VoxelGrid grid = geometry::voxelize(geometry::buildHumerusModel().mesh, vo);
  geometry::SurfaceOptions so;
  const CrackMetric crackFree =
      measureCracks(geometry::extractSurface(grid, so).toTriangleMesh(), {256, false});
  so.method = geometry::SurfaceMethod::Naive;
  const CrackMetric naive =
      measureCracks(geometry::extractSurface(grid, so).toTriangleMesh(), {256, false});
  EXPECT_EQ(crackFree.red, 0u);
  EXPECT_GT(naive.red, 0u);
  EXPECT_GT(naive.crackPercent(), 0.1);
}

TEST(CrackMetric, ImagesAreWrittenAsPng) {
  const std::string dir = test::makeTempDir("cracks");
  CrackMetricOptions options;
  options.pixels = 64;
  options.keepImages = true;
  const std::vector<std::string> paths =
      writeCrackImages(measureCracks(test::makeSphere(5.0, 32, 16), options), dir);
  ASSERT_EQ(paths.size(), 6u);
  for (const std::string& p : paths) {
    const std::string bytes = test::readBytes(p);
    ASSERT_GT(bytes.size(), 100u) << p;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << p;
  }
  EXPECT_THROW(
      writeCrackImages(measureCracks(test::makeSphere(5.0, 32, 16), options), dir + "/missing/dir"),
      InputError);
}

}  // namespace
}  // namespace osteon::validation
