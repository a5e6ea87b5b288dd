// RefinedVoxels::refineNearSegment: the bone a part's shell around a segment can reach, and
// no more; a budget leaves the rest to later calls, which continue until all are refined.
#include <limits>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

using Key = std::tuple<int, int, int>;

class RefineSegmentTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const TriangleMesh mesh = test::makeSphere(10.0, 256, 128);
    VoxelizeOptions options;
    options.voxelSizeMm = 1.2;
    grid_ = voxelize(mesh, options);
    hierarchy_ = DynamicProximityHierarchy::build(grid_, DphBuildOptions{});
  }
  RefinedVoxels make(int depth) {
    RefinementOptions options;
    options.depth = depth;
    return RefinedVoxels(grid_, hierarchy_, nullptr, options);
  }
  // The voxels with bone whose centre lies within reachMm of the segment a-b, by brute force.
  std::set<Key> expected(const glm::dvec3& a, const glm::dvec3& b, double reachMm) const {
    std::set<Key> out;
    const glm::dvec3 ab = b - a;
    for (int z = 0; z < grid_.dims().z; ++z)
      for (int y = 0; y < grid_.dims().y; ++y)
        for (int x = 0; x < grid_.dims().x; ++x) {
          if (grid_.fill({x, y, z}) == 0) continue;
          const glm::dvec3 c = grid_.voxelCentreMm({x, y, z});
          const double len2 = glm::dot(ab, ab);
          const double t = len2 > 0.0 ? std::clamp(glm::dot(c - a, ab) / len2, 0.0, 1.0) : 0.0;
          if (glm::length(a + t * ab - c) <= reachMm - 1e-9) out.insert({x, y, z});
        }
    return out;
  }
  static std::set<Key> refinedSet(const RefinedVoxels& r) {
    std::set<Key> out;
    for (const glm::ivec3& v : r.refinedVoxels()) out.insert({v.x, v.y, v.z});
    return out;
  }

  VoxelGrid grid_;
  DynamicProximityHierarchy hierarchy_;
  // A shaft half in the ball of radius 10 mm, tilted: its shell reaches bone along 6 mm of it.
  const glm::dvec3 a_{4.0, 1.0, -1.0}, b_{16.0, 3.0, 2.0};
  const double outerMm_ = 1.6;
  static constexpr std::size_t kNoLimit = std::numeric_limits<std::size_t>::max();
};

TEST_F(RefineSegmentTest, RefinesTheBoneTheShellReachesAndNoMore) {
  RefinedVoxels refined = make(2);
  int deferred = -1;
  const int created = refined.refineNearSegment(a_, b_, outerMm_, 0.0, nullptr, kNoLimit, deferred);
  EXPECT_EQ(deferred, 0);
  const std::set<Key> want = expected(a_, b_, refined.segmentRefineReachMm(outerMm_));
  ASSERT_GT(want.size(), 20u);
  EXPECT_EQ(std::size_t(created), want.size());
  // Everything it refined is within reach (those exactly on the reach may go either way).
  const std::set<Key> got = refinedSet(refined);
  const std::set<Key> wider = expected(a_, b_, refined.segmentRefineReachMm(outerMm_) + 1e-6);
  for (const Key& k : want) EXPECT_TRUE(got.count(k));
  for (const Key& k : got) EXPECT_TRUE(wider.count(k));
  // Far fewer than a sphere around the shaft's middle holds (the refinement the cutting parts
  // get), which would take bone the shell cannot reach.
  EXPECT_LT(
      got.size(),
      expected(0.5 * (a_ + b_), 0.5 * (a_ + b_), 0.5 * glm::length(b_ - a_) + outerMm_).size());
  // Again: nothing new, all kept alive.
  EXPECT_EQ(refined.refineNearSegment(a_, b_, outerMm_, 1.0, nullptr, kNoLimit, deferred), 0);
  EXPECT_EQ(refined.expire(2.5), 0);
}

TEST_F(RefineSegmentTest, ABudgetLeavesTheRestForLaterCalls) {
  RefinedVoxels all = make(2), budgeted = make(2);
  int deferred = 0;
  const int total = all.refineNearSegment(a_, b_, outerMm_, 0.0, nullptr, kNoLimit, deferred);
  int sum = 0, calls = 0;
  for (;;) {
    const int created =
        budgeted.refineNearSegment(a_, b_, outerMm_, 0.001 * calls, nullptr, 7, deferred);
    ++calls;
    EXPECT_LE(created, 7);
    sum += created;
    EXPECT_EQ(sum + deferred, total);  // what is left is what the next calls refine
    if (deferred == 0) break;
    ASSERT_LT(calls, 1000);
  }
  EXPECT_EQ(calls, (total + 6) / 7);
  EXPECT_EQ(refinedSet(budgeted), refinedSet(all));
  // Volume is conserved however the refinement was spread.
  for (const glm::ivec3& v : budgeted.refinedVoxels()) {
    std::array<Fill, kSubVoxels> fill;
    std::array<Density, kSubVoxels> density;
    ASSERT_TRUE(budgeted.subFill(v, fill, density));
    unsigned s = 0;
    for (const Fill f : fill) s += f;
    EXPECT_EQ(s, grid_.fill(v));
  }
  // A budget of 0 refines nothing and defers everything.
  RefinedVoxels none = make(2);
  EXPECT_EQ(none.refineNearSegment(a_, b_, outerMm_, 0.0, nullptr, 0, deferred), 0);
  EXPECT_EQ(deferred, total);
}

TEST_F(RefineSegmentTest, StaticRunsRefineNothing) {
  RefinedVoxels refined = make(0);
  int deferred = -1;
  EXPECT_EQ(refined.refineNearSegment(a_, b_, outerMm_, 0.0, nullptr, kNoLimit, deferred), 0);
  EXPECT_EQ(deferred, 0);
  EXPECT_EQ(refined.refinedCount(), 0u);
}

}  // namespace
}  // namespace osteon::geometry
