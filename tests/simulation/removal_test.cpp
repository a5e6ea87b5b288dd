// Material removal through the refined voxels' sample-mutation interface: held against the
// slow reference (tests/support/carve.h), and the cut shapes and ties it must get right.
#include "osteon/simulation/removal.h"

#include <algorithm>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/carve.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

using geometry::DphBuildOptions;
using geometry::DynamicProximityHierarchy;
using geometry::FineFillSource;
using geometry::kFillFull;
using geometry::RefinedVoxels;
using geometry::VoxelGrid;
using geometry::VoxelSample;

// A sphere of radius 10 mm voxelized at the seed's coarsest size, with its hierarchy and the
// mesh's fine fill.
class RemovalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    mesh_ = test::makeSphere(10.0, 256, 128);
    geometry::VoxelizeOptions options;
    options.voxelSizeMm = 1.2;
    grid_ = geometry::voxelize(mesh_, options);
    const geometry::EmbreeScene scene(mesh_);
    source_ = FineFillSource::sample(grid_, mesh_, scene);
    hierarchy_ = DynamicProximityHierarchy::build(grid_, DphBuildOptions{});
  }
  RefinedVoxels make(int depth, const FineFillSource* source) {
    geometry::RefinementOptions options;
    options.depth = depth;
    return RefinedVoxels(grid_, hierarchy_, source, options);
  }
  MaterialRemoval& removal(RefinedVoxels& refined) {
    removal_ = std::make_unique<MaterialRemoval>(refined);
    return *removal_;
  }

  geometry::TriangleMesh mesh_;
  VoxelGrid grid_;
  FineFillSource source_;
  DynamicProximityHierarchy hierarchy_;
  std::unique_ptr<MaterialRemoval> removal_;
};

// The fast removal (per-axis distances, row skips, a hierarchy query) and the reference take
// the same samples from the same bone, cut after cut, refined or not.
TEST_F(RemovalTest, EqualsTheReferenceOnRandomCuts) {
  for (const int depth : {0, 1, 2}) {
    SetUp();
    VoxelGrid referenceGrid = grid_;
    DynamicProximityHierarchy referenceHierarchy =
        DynamicProximityHierarchy::build(referenceGrid, DphBuildOptions{});
    geometry::RefinementOptions options;
    options.depth = depth;
    RefinedVoxels fast(grid_, hierarchy_, &source_, options);
    RefinedVoxels slow(referenceGrid, referenceHierarchy, &source_, options);
    MaterialRemoval removal(fast);
    std::mt19937 rng(std::mt19937::result_type(1234 + depth));
    std::uniform_real_distribution<double> at(-9.0, 9.0), radius(0.6, 2.5);
    std::uint64_t removed = 0;
    for (int k = 0; k < 150; ++k) {
      const glm::dvec3 a(at(rng), at(rng), at(rng));
      const glm::dvec3 b = k % 3 == 0 ? a : a + glm::dvec3(at(rng), at(rng), at(rng)) * 0.3;
      const CutVolume cut{a, b, radius(rng), k % 5 == 4};
      const double t = 0.01 * k;
      fast.refineAround(cut.centreMm(), cut.boundingRadiusMm() + 0.6, t);
      slow.refineAround(cut.centreMm(), cut.boundingRadiusMm() + 0.6, t);
      const int decrement = 1 + k % 20;
      const RemovalResult r = removal.removeIn(cut, decrement);
      const test::Carved c =
          test::carve(slow, test::Cut{a, b, cut.radiusMm, cut.sideOnly}, decrement);
      ASSERT_EQ(r.removedFill, c.removedFill) << "depth " << depth << " cut " << k;
      ASSERT_EQ(r.samplesRemoved, c.samplesRemoved) << "depth " << depth << " cut " << k;
      ASSERT_EQ(r.samplesDecremented, c.samplesDecremented) << "depth " << depth << " cut " << k;
      ASSERT_EQ(r.voxelsEmptied, c.voxelsEmptied) << "depth " << depth << " cut " << k;
      removed += r.removedFill;
    }
    EXPECT_GT(removed, 0u);
    EXPECT_EQ(grid_.totalFill(), referenceGrid.totalFill());
    EXPECT_EQ(hierarchy_.validateAgainst(grid_), "");
    EXPECT_EQ(removal.cutOverflows(), 0u);
  }
}

// Cuts whose axis runs through voxel centres with a radius of whole voxels put centres exactly
// on the cut's surface: every centre contains() takes goes, whatever the query's rounding.
TEST_F(RemovalTest, StaticCutsTakeEveryVoxelCentreOnTheirSurface) {
  RefinedVoxels refined = make(0, &source_);
  const double vs = grid_.voxelSizeMm();
  std::vector<glm::ivec3> bone;
  for (int z = 0; z < grid_.dims().z; ++z)
    for (int y = 0; y < grid_.dims().y; ++y)
      for (int x = 0; x < grid_.dims().x; ++x)
        if (grid_.fill({x, y, z}) == kFillFull) bone.push_back({x, y, z});
  std::mt19937 rng(2718);
  std::uniform_int_distribution<std::size_t> pick(0, bone.size() - 1);
  const glm::dvec3 directions[] = {{0, 0, 4}, {3, 4, 0},  {0, 3, 4},
                                   {1, 2, 2}, {2, -1, 2}, {4, 0, -3}};
  std::size_t onSurface = 0;
  for (int k = 0; k < 120; ++k) {
    const glm::dvec3 a = grid_.voxelCentreMm(bone[pick(rng)]);
    const glm::dvec3 b = a + vs * directions[k % 6];
    const CutVolume cut{a, b, vs * double(1 + k % 3), false};
    // The voxels of this cut before it, to check against after.
    std::vector<glm::ivec3> inside;
    for (int z = 0; z < grid_.dims().z; ++z)
      for (int y = 0; y < grid_.dims().y; ++y)
        for (int x = 0; x < grid_.dims().x; ++x) {
          const glm::dvec3 c = grid_.voxelCentreMm({x, y, z});
          if (grid_.fill({x, y, z}) == 0 || !cut.contains(c)) continue;
          inside.push_back({x, y, z});
          const glm::dvec3 ab = b - a;
          const double t = std::clamp(glm::dot(c - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
          if (std::abs(glm::length(c - (a + t * ab)) - cut.radiusMm) < 1e-9) ++onSurface;
        }
    removal(refined).removeIn(cut, 1000);
    for (const glm::ivec3& v : inside) {
      ASSERT_EQ(grid_.fill(v), 0) << "cut " << k << " left voxel (" << v.x << ", " << v.y << ", "
                                  << v.z << ")";
    }
  }
  EXPECT_GT(onSurface, 100u);  // the ties this is about did occur
  EXPECT_EQ(hierarchy_.validateAgainst(grid_), "");
}

TEST(CutVolume, SphereCapsuleAndOpenCylinder) {
  const CutVolume s = CutVolume::sphere({1, 2, 3}, 2.0);
  EXPECT_TRUE(s.contains({1, 2, 4.99}));
  EXPECT_FALSE(s.contains({1, 2, 5.01}));
  EXPECT_DOUBLE_EQ(s.boundingRadiusMm(), 2.0);
  CutVolume c{{0, 0, 0}, {10, 0, 0}, 1.0, false};
  EXPECT_TRUE(c.contains({5, 0.99, 0}));
  EXPECT_FALSE(c.contains({5, 1.01, 0}));
  EXPECT_TRUE(c.contains({-0.9, 0, 0}));  // rounded end
  EXPECT_DOUBLE_EQ(c.boundingRadiusMm(), 6.0);
  c.sideOnly = true;  // a shaver cuts with its side only
  EXPECT_FALSE(c.contains({-0.1, 0, 0}));
  EXPECT_FALSE(c.contains({10.1, 0.2, 0}));
  EXPECT_TRUE(c.contains({9.9, 0.2, 0}));
}

TEST_F(RemovalTest, CylinderRemovalTakesExactlyTheSamplesInside) {
  for (const int depth : {0, 2}) {
    SetUp();
    RefinedVoxels refined = make(depth, &source_);
    const CutVolume cut{{-4, -1, 0.3}, {4, 1, 0.3}, 1.5, true};
    refined.refineAround(cut.centreMm(), cut.boundingRadiusMm(), 0.0);
    std::uint64_t inside = 0, samples = 0;
    refined.forEachSampleInSphere(cut.centreMm(), cut.boundingRadiusMm(),
                                  [&](const VoxelSample& s) {
                                    if (cut.contains(s.centreMm)) {
                                      inside += s.fill;
                                      ++samples;
                                    }
                                  });
    ASSERT_GT(samples, 20u) << "depth " << depth;
    const std::uint64_t before = grid_.totalFill();
    // Decrement past every density: one call removes every sample inside, nothing else.
    const RemovalResult r = removal(refined).removeIn(cut, 1000);
    EXPECT_EQ(r.removedFill, inside) << "depth " << depth;
    EXPECT_EQ(r.samplesRemoved, samples) << "depth " << depth;
    EXPECT_EQ(grid_.totalFill(), before - inside) << "depth " << depth;
    std::uint64_t left = 0;
    refined.forEachSampleInSphere(cut.centreMm(), cut.boundingRadiusMm(),
                                  [&](const VoxelSample& s) {
                                    if (cut.contains(s.centreMm)) ++left;
                                  });
    EXPECT_EQ(left, 0u) << "depth " << depth;
  }
}

}  // namespace
}  // namespace osteon::simulation
