// The lattice build against the seed's insertion build (the slow reference): the same query
// answers, as sets, on random voxels, the built-in humerus and a shared bone, before and after
// removals; one structure for any input order and any thread count.
#include <algorithm>
#include <array>
#include <filesystem>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/voxels/voxelizer.h"

namespace osteon::geometry {
namespace {

using Answer = std::vector<std::array<int, 3>>;

DphBuildOptions insertion() {
  DphBuildOptions options;
  options.method = DphBuildMethod::kInsertion;
  return options;
}

Answer sorted(Answer a) {
  std::sort(a.begin(), a.end());
  return a;
}

// Spheres, capsules and nearest voxels around random points of `voxels`: both hierarchies give
// the same voxels (the walk's order differs with the structure, so compared as sorted lists).
void expectSameAnswers(const DynamicProximityHierarchy& lattice,
                       const DynamicProximityHierarchy& reference,
                       const std::vector<glm::ivec3>& voxels, int queries, double maxRadiusMm,
                       unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, voxels.size() - 1);
  std::uniform_real_distribution<double> jitter(-2.0, 2.0), radius(0.0, maxRadiusMm);
  DphQueryScratch s1, s2;
  const double vs = lattice.voxelSizeMm();
  for (int q = 0; q < queries; ++q) {
    const glm::dvec3 a = lattice.voxelCentreMm(voxels[pick(rng)]) +
                         vs * glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
    const glm::dvec3 b = a + vs * 3.0 * glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
    const double r = radius(rng);
    Answer got, want;
    const auto into = [](Answer& out) {
      return [&out](const glm::ivec3& v) { out.push_back({v.x, v.y, v.z}); };
    };
    lattice.forEachVoxelInSphere(a, r, s1, into(got));
    reference.forEachVoxelInSphere(a, r, s2, into(want));
    ASSERT_EQ(sorted(got), sorted(want)) << "sphere query " << q;
    got.clear();
    want.clear();
    lattice.forEachVoxelInCapsule(a, b, r, s1, into(got));
    reference.forEachVoxelInCapsule(a, b, r, s2, into(want));
    ASSERT_EQ(sorted(got), sorted(want)) << "capsule query " << q;
    glm::ivec3 n1, n2;
    double d1 = 0.0, d2 = 0.0;
    ASSERT_EQ(lattice.nearestVoxel(a, s1, n1, d1), reference.nearestVoxel(a, s2, n2, d2));
    EXPECT_EQ(d1, d2) << "nearest "
                      << q;  // the same distance, computed the same way (ties may differ)
  }
}

// Both builds, checked, compared; then the same removals from both, compared again.
void expectLatticeMatchesInsertion(const std::vector<glm::ivec3>& voxels, glm::dvec3 originMm,
                                   double voxelMm, int xi, double maxRadiusMm, int queries) {
  DphBuildOptions options;
  options.expansionRatio = xi;
  DphBuildOptions reference = insertion();
  reference.expansionRatio = xi;
  auto lattice = DynamicProximityHierarchy::build(voxels, options, originMm, voxelMm);
  auto slow = DynamicProximityHierarchy::build(voxels, reference, originMm, voxelMm);
  ASSERT_TRUE(lattice.latticeBuilt());
  ASSERT_EQ(lattice.validate(), "");
  ASSERT_EQ(slow.validate(), "");
  ASSERT_EQ(lattice.voxelCount(), voxels.size());
  expectSameAnswers(lattice, slow, voxels, queries, maxRadiusMm, 11);
  std::mt19937 rng(12);
  std::vector<glm::ivec3> gone = voxels;
  std::shuffle(gone.begin(), gone.end(), rng);
  gone.resize(gone.size() / 2);
  for (const glm::ivec3& v : gone) {
    ASSERT_TRUE(lattice.removeVoxel(v));
    ASSERT_TRUE(slow.removeVoxel(v));
    ASSERT_FALSE(lattice.contains(v));
  }
  ASSERT_FALSE(lattice.removeVoxel(gone.front()));
  ASSERT_EQ(lattice.validate(), "");
  expectSameAnswers(lattice, slow, voxels, queries, maxRadiusMm, 13);
}

std::vector<glm::ivec3> occupied(const VoxelGrid& grid) {
  std::vector<glm::ivec3> out;
  const glm::ivec3 d = grid.dims();
  for (int z = 0; z < d.z; ++z)
    for (int y = 0; y < d.y; ++y)
      for (int x = 0; x < d.x; ++x)
        if (grid.fill({x, y, z}) > 0) out.push_back({x, y, z});
  return out;
}

TEST(DphLattice, AnswersAsTheInsertionBuildOnRandomVoxels) {
  for (const int xi : {3, 5, 7}) {
    std::mt19937 rng{unsigned(xi)};
    std::bernoulli_distribution keep(0.3);
    std::vector<glm::ivec3> voxels;
    for (int z = -5; z < 20; ++z)
      for (int y = 0; y < 17; ++y)
        for (int x = -30; x < -8; ++x)
          if (keep(rng)) voxels.push_back({x, y, z});
    std::shuffle(voxels.begin(), voxels.end(), rng);
    expectLatticeMatchesInsertion(voxels, {-3.0, 1.5, 2.0}, 0.7, xi, 6.0, 150);
  }
}

TEST(DphLattice, AnswersAsTheInsertionBuildOnTheBuiltInHumerus) {
  VoxelizeOptions options;
  options.voxelSizeMm = 1.2;
  const VoxelGrid grid = voxelize(buildHumerusModel().mesh, options);
  expectLatticeMatchesInsertion(occupied(grid), grid.originMm(), grid.voxelSizeMm(), 3, 6.0, 300);
  const auto h = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  EXPECT_EQ(h.validateAgainst(grid), "");
}

TEST(DphLattice, AnswersAsTheInsertionBuildOnASharedBone) {
  const std::string path = std::string(OSTEON_SHARED_DATA_DIR) + "/fibula_L_vhm_denver.stl";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found at " << path;
  VoxelizeOptions options;
  options.voxelSizeMm = 1.0;
  const VoxelGrid grid = voxelize(readMesh(path), options);
  expectLatticeMatchesInsertion(occupied(grid), grid.originMm(), grid.voxelSizeMm(), 3, 5.0, 200);
}

void expectIdentical(const DynamicProximityHierarchy& a, const DynamicProximityHierarchy& b) {
  ASSERT_EQ(a.levelCount(), b.levelCount());
  for (int L = 0; L < a.levelCount(); ++L) {
    ASSERT_EQ(a.nodeSlots(L), b.nodeSlots(L));
    for (std::uint32_t i = 0; i < a.nodeSlots(L); ++i) {
      ASSERT_EQ(a.centre(L, i), b.centre(L, i));
      ASSERT_EQ(a.parent(L, i), b.parent(L, i));
      if (L > 0) {
        ASSERT_EQ(a.childBegin(L, i), b.childBegin(L, i));
        ASSERT_EQ(a.childEnd(L, i), b.childEnd(L, i));
      }
    }
  }
}

TEST(DphLattice, OneStructureForAnyInputOrderAndThreadCount) {
  VoxelizeOptions options;
  options.voxelSizeMm = 0.9;
  const VoxelGrid grid = voxelize(buildHumerusModel().mesh, options);
  std::vector<glm::ivec3> voxels = occupied(grid);
  DynamicProximityHierarchy one, many, shuffled;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = DynamicProximityHierarchy::build(voxels, DphBuildOptions{});
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
    many = DynamicProximityHierarchy::build(voxels, DphBuildOptions{});
  }
  std::mt19937 rng(3);
  std::shuffle(voxels.begin(), voxels.end(), rng);
  shuffled = DynamicProximityHierarchy::build(voxels, DphBuildOptions{});
  expectIdentical(one, many);
  expectIdentical(one, shuffled);
  // The same walk, voxel for voxel and in order, on both.
  DphQueryScratch s1, s2;
  for (std::size_t i = 0; i < voxels.size(); i += 997) {
    Answer x, y;
    const glm::dvec3 c = one.voxelCentreMm(voxels[i]);
    one.forEachVoxelInSphere(c, 3.0, s1, [&](const glm::ivec3& v) {
      x.push_back({v.x, v.y, v.z});
    });
    many.forEachVoxelInSphere(c, 3.0, s2, [&](const glm::ivec3& v) {
      y.push_back({v.x, v.y, v.z});
    });
    ASSERT_EQ(x, y);
  }
}

// The grid build reads cells straight from the bricks; it must give the voxel-list build's
// structure node for node, on any thread count.
void expectGridBuildAsVoxelList(const VoxelGrid& grid) {
  const std::vector<glm::ivec3> voxels = occupied(grid);
  const auto fromList = DynamicProximityHierarchy::build(voxels, DphBuildOptions{}, grid.originMm(),
                                                         grid.voxelSizeMm());
  DynamicProximityHierarchy one, many;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
    many = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  }
  ASSERT_EQ(one.validateAgainst(grid), "");
  ASSERT_EQ(one.voxelCount(), voxels.size());
  expectIdentical(one, fromList);
  expectIdentical(many, fromList);
  expectSameAnswers(one, fromList, voxels, 100, 4.0 * grid.voxelSizeMm(), 5);
}

TEST(DphLattice, TheGridBuildIsTheVoxelListBuild) {
  // Random voxels over bricks of every kind: cells straddle 64-bit words (x up to 150) and
  // bricks; uniform full bricks and edge bricks beside them.
  VoxelGrid grid({150, 37, 29}, glm::dvec3(-4.0, 2.0, 1.0), 0.5);
  std::mt19937 rng(21);
  std::bernoulli_distribution keep(0.3);
  for (int z = 0; z < 29; ++z)
    for (int y = 0; y < 37; ++y)
      for (int x = 0; x < 150; ++x)
        if (keep(rng)) grid.set({x, y, z}, Fill(1 + rng() % kFillFull), 3);
  grid.setBrickUniform(grid.brickIndex({2, 1, 1}), kFillFull, 5);
  grid.setBrickUniform(grid.brickIndex({18, 4, 3}), kFillHalf, 5);  // the edge bricks, padded
  expectGridBuildAsVoxelList(grid);
  VoxelizeOptions options;
  for (const double vs : {1.2, 0.9}) {
    options.voxelSizeMm = vs;
    expectGridBuildAsVoxelList(voxelize(buildHumerusModel().mesh, options));
  }
  const std::string path = std::string(OSTEON_SHARED_DATA_DIR) + "/fibula_L_vhm_denver.stl";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found at " << path;
  options.voxelSizeMm = 1.0;
  expectGridBuildAsVoxelList(voxelize(readMesh(path), options));
}

TEST(DphLattice, GridsOfNoneOneAndTwoVoxels) {
  VoxelGrid grid({20, 20, 20}, glm::dvec3(0.0), 1.0);
  EXPECT_EQ(DynamicProximityHierarchy::build(grid, DphBuildOptions{}).voxelCount(), 0u);
  grid.set({9, 3, 17}, kFillFull, 1);
  const auto one = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  EXPECT_EQ(one.validateAgainst(grid), "");
  EXPECT_EQ(one.levelCount(), 1);
  grid.set({10, 3, 17}, 1, 1);
  expectGridBuildAsVoxelList(grid);
  auto two = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  EXPECT_TRUE(two.removeVoxel({9, 3, 17}));
  EXPECT_FALSE(two.contains({9, 3, 17}));
  EXPECT_TRUE(two.contains({10, 3, 17}));
  EXPECT_EQ(two.validate(), "");
  EXPECT_TRUE(two.removeVoxel({10, 3, 17}));
  EXPECT_EQ(two.root(), DynamicProximityHierarchy::kNone);
  EXPECT_EQ(two.validate(), "");
}

TEST(DphLattice, CellsTileTheLatticeFromTheLowestVoxel) {
  // Two voxels on either side of 0 share every cell above level 0 (the lattice starts at -1).
  const auto h = DynamicProximityHierarchy::build({{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}},
                                                  DphBuildOptions{});
  ASSERT_EQ(h.validate(), "");
  ASSERT_EQ(h.levelCount(), 3);
  EXPECT_EQ(h.nodeCount(1), 2u);  // cells x in [-1, 1] and [2, 4]
  EXPECT_EQ(h.centre(1, 0), glm::ivec3(0, 1, 1));
  EXPECT_EQ(h.centre(1, 1), glm::ivec3(3, 1, 1));
  EXPECT_EQ(h.nodeCount(2), 1u);
  EXPECT_EQ(h.halfWidth(2), 4);
}

TEST(DphLattice, KeysTooWideFallBackToInsertion) {
  // 2^21 voxels across at xi 3 need 14 base-3 digits, 27^14 > 2^64: built by insertion.
  const std::vector<glm::ivec3> far = {{-(1 << 20), 0, 0}, {(1 << 20) - 1, 0, 0}, {5, 5, 5}};
  auto h = DynamicProximityHierarchy::build(far, DphBuildOptions{});
  EXPECT_FALSE(h.latticeBuilt());
  EXPECT_EQ(h.validate(), "");
  for (const glm::ivec3& v : far) EXPECT_TRUE(h.contains(v));
  // Wide but within 64 bits: the lattice, with the (key, index) pairs sorted unpacked.
  const std::vector<glm::ivec3> wide = {
      {-(1 << 19), 0, 0}, {(1 << 19), 7, 0}, {5, 5, 5}, {6, 5, 5}, {7, 5, 5}};
  auto w = DynamicProximityHierarchy::build(wide, DphBuildOptions{});
  EXPECT_TRUE(w.latticeBuilt());
  EXPECT_EQ(w.validate(), "");
  for (const glm::ivec3& v : wide) EXPECT_TRUE(w.contains(v));
  EXPECT_FALSE(w.contains({5, 5, 6}));
  EXPECT_FALSE(w.contains({(1 << 19) + 1, 7, 0}));
}

}  // namespace
}  // namespace osteon::geometry
