#include "osteon/geometry/voxels/voxel_grid.h"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace osteon::geometry {
namespace {

TEST(VoxelGrid, DimsAndBrickDims) {
  const VoxelGrid grid({13, 9, 21}, {1.0, 2.0, 3.0}, 0.5);
  EXPECT_EQ(grid.dims(), glm::ivec3(13, 9, 21));
  EXPECT_EQ(grid.brickDims(), glm::ivec3(2, 2, 3));
  EXPECT_EQ(grid.brickCount(), 12u);
  EXPECT_EQ(grid.voxelCount(), 13u * 9u * 21u);
  EXPECT_DOUBLE_EQ(grid.voxelVolumeMm3(), 0.125);
  EXPECT_EQ(VoxelGrid({8, 16, 1}, glm::dvec3(0.0), 1.0).brickDims(), glm::ivec3(1, 2, 1));
  EXPECT_EQ(VoxelGrid({9, 17, 7}, glm::dvec3(0.0), 1.0).brickDims(), glm::ivec3(2, 3, 1));
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    EXPECT_EQ(grid.brickIndex(grid.brickCoord(brick)), brick);
  }
  EXPECT_EQ(grid.allocatedBrickCount(), 0u);
  EXPECT_TRUE(grid.dirtyBricks().empty());
}

TEST(VoxelGrid, TransformsAreInverse) {
  const VoxelGrid grid({20, 30, 40}, {-12.5, 3.25, 100.0}, 0.3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> g(-5.0, 45.0);
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 p(g(rng), g(rng), g(rng));
    const glm::dvec3 w = grid.worldFromGrid(p);
    const glm::dvec3 back = grid.gridFromWorld(w);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(back[a], p[a], 1e-12);
  }
  // Corner of voxel 0 is the origin; a voxel's centre lies in that voxel.
  EXPECT_EQ(grid.worldFromGrid(glm::dvec3(0.0)), grid.originMm());
  for (const glm::ivec3 ijk : {glm::ivec3(0), glm::ivec3(19, 29, 39), glm::ivec3(-3, 7, 50)}) {
    const glm::dvec3 c = grid.voxelCentreMm(ijk);
    EXPECT_EQ(grid.voxelFromWorld(c), ijk);
    const glm::dvec3 expected = grid.originMm() + (glm::dvec3(ijk) + 0.5) * 0.3;
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(c[a], expected[a], 1e-12);
  }
  // Floor, not truncation, below the origin.
  EXPECT_EQ(grid.voxelFromWorld(grid.originMm() - 0.01), glm::ivec3(-1));
}

TEST(VoxelGrid, OutsideReadsEmpty) {
  VoxelGrid grid({5, 6, 7}, glm::dvec3(0.0), 1.0);
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    grid.setBrickUniform(brick, kFillFull, 42);
  }
  EXPECT_EQ(grid.fill({4, 5, 6}), kFillFull);
  EXPECT_EQ(grid.density({4, 5, 6}), 42);
  for (const glm::ivec3 p : {glm::ivec3(-1, 0, 0), glm::ivec3(5, 0, 0), glm::ivec3(0, 6, 0),
                             glm::ivec3(0, 0, 7), glm::ivec3(7, 7, 7)}) {
    EXPECT_FALSE(grid.inBounds(p));
    EXPECT_EQ(grid.fill(p), 0);
    EXPECT_EQ(grid.density(p), 0);
  }
  EXPECT_THROW(grid.set({5, 0, 0}, 1, 1), std::out_of_range);
}

// fillAndDensity reads what fill and density read, in uniform bricks, stored ones and outside.
TEST(VoxelGrid, FillAndDensityTogether) {
  VoxelGrid grid({12, 9, 10}, glm::dvec3(0.0), 1.0);
  grid.setBrickUniform(0, kFillFull, 40);
  grid.set({9, 3, 2}, 1234, -7);
  for (const glm::ivec3 p : {glm::ivec3(1, 1, 1), glm::ivec3(9, 3, 2), glm::ivec3(9, 3, 3),
                             glm::ivec3(-1, 0, 0), glm::ivec3(12, 0, 0)}) {
    Fill f = 1;
    Density d = 1;
    grid.fillAndDensity(p, f, d);
    EXPECT_EQ(f, grid.fill(p));
    EXPECT_EQ(d, grid.density(p));
  }
  Fill f = 0;
  Density d = 0;
  grid.fillAndDensity({9, 3, 2}, f, d);
  EXPECT_EQ(f, 1234);
  EXPECT_EQ(d, -7);
}

TEST(VoxelGrid, SetMaterialisesOnlyWhenNeededAndMarksDirty) {
  VoxelGrid grid({16, 16, 16}, glm::dvec3(0.0), 1.0);
  grid.setBrickUniform(0, 100, 5);
  grid.clearDirty();
  grid.set({1, 2, 3}, 100, 5);  // the brick's own value: nothing to store
  EXPECT_EQ(grid.allocatedBrickCount(), 0u);
  EXPECT_TRUE(grid.dirtyBricks().empty());

  grid.set({1, 2, 3}, 101, 5);
  EXPECT_EQ(grid.allocatedBrickCount(), 1u);
  EXPECT_TRUE(grid.brickAllocated(0));
  EXPECT_EQ(grid.fill({1, 2, 3}), 101);
  EXPECT_EQ(grid.fill({1, 2, 4}), 100);  // the rest keeps the uniform value
  EXPECT_EQ(grid.density({7, 7, 7}), 5);
  ASSERT_NE(grid.brickData(0), nullptr);
  EXPECT_EQ(grid.brickData(0)->fill[std::size_t(VoxelGrid::voxelInBrick({1, 2, 3}))], 101);
  EXPECT_EQ(grid.dirtyBricks(), std::vector<std::size_t>{0});

  // Density alone does not dirty a brick (the surface depends on fill only); fill does.
  const std::size_t far = grid.brickIndex({1, 1, 1});
  grid.set({15, 15, 15}, 0, -9);
  EXPECT_FALSE(grid.brickDirty(far));
  grid.set({15, 15, 14}, 7, -9);
  EXPECT_TRUE(grid.brickDirty(far));
  EXPECT_EQ(grid.dirtyBricks(), (std::vector<std::size_t>{0, far}));
  grid.clearDirty();
  EXPECT_TRUE(grid.dirtyBricks().empty());
  EXPECT_EQ(grid.density({15, 15, 15}), -9);  // clearing flags keeps the data

  grid.markBrickDirty(3);
  EXPECT_EQ(grid.dirtyBricks(), std::vector<std::size_t>{3});
  grid.clearDirty();
  (void)grid.materialiseBrick(5);  // same values: not dirty
  EXPECT_FALSE(grid.brickDirty(5));
  grid.setBrickUniform(5, 1, 1);
  EXPECT_FALSE(grid.brickAllocated(5));
  EXPECT_EQ(grid.fill({8, 0, 8}), 1);
}

TEST(VoxelGrid, CompactFreesBricksMadeUniformAgain) {
  VoxelGrid grid({16, 8, 8}, glm::dvec3(0.0), 1.0);
  grid.set({1, 1, 1}, 200, 3);  // brick 0
  grid.set({9, 1, 1}, 200, 3);  // brick 1
  EXPECT_EQ(grid.allocatedBrickCount(), 2u);
  EXPECT_EQ(grid.compact(), 0u);
  grid.set({1, 1, 1}, 0, 0);  // brick 0 is all zero again
  EXPECT_EQ(grid.compact(), 1u);
  EXPECT_FALSE(grid.brickAllocated(0));
  EXPECT_TRUE(grid.brickAllocated(1));
  EXPECT_EQ(grid.brickUniformFill(0), 0);
  EXPECT_EQ(grid.fill({9, 1, 1}), 200);

  // Made uniform at a new value: the uniform value follows.
  VoxelGrid::Brick& b = grid.materialiseBrick(1);
  b.fill.fill(77);
  b.density.fill(-4);
  EXPECT_EQ(grid.compact(), 1u);
  EXPECT_EQ(grid.allocatedBrickCount(), 0u);
  EXPECT_EQ(grid.brickUniformFill(1), 77);
  EXPECT_EQ(grid.brickUniformDensity(1), -4);
  EXPECT_EQ(grid.fill({15, 7, 7}), 77);
}

// An edge brick's padding lies outside the grid and keeps the value the brick was
// materialised from; compact() must judge the brick by its grid voxels alone.
TEST(VoxelGrid, CompactFreesEdgeBricksWhoseGridVoxelsAgree) {
  VoxelGrid grid({9, 8, 8}, glm::dvec3(0.0), 1.0);  // brick 1 holds only x = 8
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y) grid.set({8, y, z}, kFillFull, 5);
  EXPECT_EQ(grid.compact(), 1u);
  EXPECT_EQ(grid.allocatedBrickCount(), 0u);
  EXPECT_EQ(grid.fill({8, 3, 3}), kFillFull);
}

// A grid with random bricks, uniform bricks and edge bricks, from a fixed seed.
VoxelGrid makeRandomGrid(std::mt19937& rng) {
  VoxelGrid grid({21, 13, 10}, {0.5, -1.0, 2.0}, 0.4);
  std::uniform_int_distribution<int> value(0, 255);
  std::uniform_int_distribution<int> pick(0, 2);
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    if (pick(rng) == 0) {
      grid.setBrickUniform(brick, Fill(value(rng)), Density(value(rng) - 100));
      continue;
    }
    // A high background: an edge brick's padding beyond the grid then holds it too.
    grid.setBrickUniform(brick, 250, 7);
    const glm::ivec3 lo = grid.brickCoord(brick) * VoxelGrid::kBrickSize;
    const glm::ivec3 hi = glm::min(lo + VoxelGrid::kBrickSize, grid.dims());
    for (int z = lo.z; z < hi.z; ++z)
      for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x)
          if (pick(rng) != 0) grid.set({x, y, z}, Fill(value(rng)), Density(value(rng) * 3));
  }
  // A full uniform edge brick: only its voxels inside the grid count.
  grid.setBrickUniform(grid.brickCount() - 1, kFillFull, 1);
  return grid;
}

TEST(VoxelGrid, TotalsMatchBruteForce) {
  std::mt19937 rng(12345);
  const VoxelGrid grid = makeRandomGrid(rng);
  ASSERT_GT(grid.allocatedBrickCount(), 0u);
  const glm::ivec3 n = grid.dims();
  for (const Fill minFill : {Fill(0), Fill(1), kFillHalf, Fill(200), kFillFull}) {
    std::uint64_t expected = 0;
    for (int z = 0; z < n.z; ++z)
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x) expected += grid.fill({x, y, z}) >= minFill ? 1u : 0u;
    EXPECT_EQ(grid.countVoxels(minFill), expected) << int(minFill);
  }
  EXPECT_EQ(grid.countVoxels(0), grid.voxelCount());
  double fillSum = 0.0;
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) fillSum += grid.fill({x, y, z}) / double(kFillFull);
  EXPECT_NEAR(grid.filledVolumeMm3(), fillSum * grid.voxelVolumeMm3(), 1e-9);
}

TEST(VoxelGrid, MemoryGrowsWithAllocatedBricks) {
  VoxelGrid grid({256, 256, 256}, glm::dvec3(0.0), 0.1);
  const std::size_t sparse = grid.memoryBytes();
  EXPECT_LT(sparse, std::size_t(1) << 20);
  grid.set({0, 0, 0}, 1, 1);
  const std::size_t one = grid.memoryBytes();
  EXPECT_GE(one, sparse + sizeof(VoxelGrid::Brick));
  grid.set({100, 100, 100}, 1, 1);
  EXPECT_GE(grid.memoryBytes(), one + sizeof(VoxelGrid::Brick));
  grid.set({0, 0, 0}, 0, 0);
  grid.set({100, 100, 100}, 0, 0);
  EXPECT_EQ(grid.compact(), 2u);
  EXPECT_EQ(grid.memoryBytes(), sparse);
}

TEST(VoxelGrid, ConstructorRejectsBadArguments) {
  const glm::dvec3 o(0.0);
  EXPECT_THROW(VoxelGrid({0, 1, 1}, o, 1.0), std::invalid_argument);
  EXPECT_THROW(VoxelGrid({1, 0, 1}, o, 1.0), std::invalid_argument);
  EXPECT_THROW(VoxelGrid({1, 1, -4}, o, 1.0), std::invalid_argument);
  EXPECT_THROW(VoxelGrid({1, 1, 1}, o, 0.0), std::invalid_argument);
  EXPECT_THROW(VoxelGrid({1, 1, 1}, o, -0.5), std::invalid_argument);
  EXPECT_THROW(VoxelGrid({1, 1, 1}, o, std::numeric_limits<double>::quiet_NaN()),
               std::invalid_argument);
  EXPECT_THROW(VoxelGrid({1, 1, 1}, o, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
  EXPECT_THROW(VoxelGrid({65536, 65536, 2}, o, 1.0), std::invalid_argument);  // 2^33
  EXPECT_THROW(VoxelGrid({100000, 100000, 100000}, o, 1.0), std::invalid_argument);
  // Few voxels but a huge brick table (each brick padded to 8^3), and an axis near INT_MAX.
  EXPECT_THROW(VoxelGrid({1, 1, 1 << 30}, o, 1.0), std::invalid_argument);
  EXPECT_THROW(VoxelGrid({2147483647, 1, 1}, o, 1.0), std::invalid_argument);
  EXPECT_NO_THROW(VoxelGrid({1, 1, 1}, o, 1e-3));
}

}  // namespace
}  // namespace osteon::geometry

namespace osteon::geometry {
namespace {

TEST(VoxelGridTotals, TotalFillEqualsTheSumOverEveryVoxel) {
  VoxelGrid g({19, 10, 9}, glm::dvec3(0.0), 0.5);  // edge bricks partly outside the grid
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> fill(0, kFillFull);
  for (int i = 0; i < 400; ++i)
    g.set({int(rng() % 19), int(rng() % 10), int(rng() % 9)}, Fill(fill(rng)), 1);
  g.setBrickUniform(g.brickIndex({1, 1, 0}), kFillFull, 3);
  std::uint64_t sum = 0;
  for (int z = 0; z < 9; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 19; ++x) sum += g.fill({x, y, z});
  EXPECT_EQ(g.totalFill(), sum);
  EXPECT_DOUBLE_EQ(g.filledVolumeMm3(), double(sum) / kFillFull * 0.125);
}

TEST(VoxelGridTotals, SpareBricksServeSetAndComeBackWhenFreed) {
  VoxelGrid g({16, 16, 16}, glm::dvec3(0.0), 1.0);
  g.reserveSpareBricks(2);
  EXPECT_EQ(g.spareBricks(), 2u);
  const std::size_t before = g.memoryBytes();
  g.set({0, 0, 0}, 100, 1);  // brick 0 from the pool
  g.set({9, 0, 0}, 100, 1);  // brick 1 from the pool
  EXPECT_EQ(g.spareBricks(), 0u);
  EXPECT_EQ(g.spareMisses(), 0u);
  EXPECT_EQ(g.memoryBytes(), before);  // the same bricks, now in use
  g.set({0, 9, 0}, 100, 1);            // the pool is empty: allocated, and counted
  EXPECT_EQ(g.spareMisses(), 1u);
  EXPECT_EQ(g.fill({0, 9, 0}), 100);
  EXPECT_EQ(g.fill({1, 9, 0}), 0);  // the rest of the brick keeps its uniform value
  g.setBrickUniform(g.brickIndex({0, 0, 0}), 0, 0);
  EXPECT_EQ(g.spareBricks(), 1u);  // back in the pool
  g.set({0, 0, 9}, 7, 1);
  EXPECT_EQ(g.spareMisses(), 1u);
  EXPECT_EQ(g.fill({0, 0, 8}), 0);  // a recycled brick starts from the uniform value, not old data
  EXPECT_EQ(g.fill({0, 0, 9}), 7);
}

}  // namespace
}  // namespace osteon::geometry
