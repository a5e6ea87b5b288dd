// Splitting validate's cases into shards: which groups exist, their keys, and the
// deterministic longest-processing-time assignment.
#include "osteon/validation/shard.h"

#include <algorithm>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "support/shapes.h"

namespace osteon::validation {
namespace {

TEST(AssignShards, LongestFirstToTheLightestShard) {
  // 5 -> 0; 4 -> 1; 3 -> 1 (4 < 5); 2 -> 0 (5 < 7); 1 -> 0 (7 = 7: the lower shard).
  EXPECT_EQ(assignShards({5, 1, 4, 2, 3}, 2), (std::vector<std::size_t>{0, 0, 1, 0, 1}));
  // Equal costs go in index order, round the shards.
  EXPECT_EQ(assignShards({1, 1, 1, 1}, 3), (std::vector<std::size_t>{0, 1, 2, 0}));
  // More shards than groups: the rest stay empty.
  EXPECT_EQ(assignShards({2, 3}, 4), (std::vector<std::size_t>{1, 0}));
  EXPECT_EQ(assignShards({7}, 1), (std::vector<std::size_t>{0}));
  EXPECT_TRUE(assignShards({}, 3).empty());
  EXPECT_THROW(assignShards({1.0}, 0), std::invalid_argument);
}

// Balanced by cost, not count: the heaviest shard exceeds the lightest by at most one group
// (the last put on it went to the lightest shard then), and the same costs split the same way.
TEST(AssignShards, BalancedAndDeterministic) {
  std::mt19937 random(24);
  std::uniform_real_distribution<double> cost(1.0, 1000.0);
  for (const std::size_t shards : {2u, 5u, 16u}) {
    std::vector<double> costs(200);
    for (double& c : costs) c = cost(random);
    const std::vector<std::size_t> shardOf = assignShards(costs, shards);
    EXPECT_EQ(assignShards(costs, shards), shardOf);
    std::vector<double> load(shards, 0.0);
    for (std::size_t i = 0; i < costs.size(); ++i) {
      ASSERT_LT(shardOf[i], shards);
      load[shardOf[i]] += costs[i];
    }
    const auto [lightest, heaviest] = std::minmax_element(load.begin(), load.end());
    EXPECT_LE(*heaviest - *lightest, *std::max_element(costs.begin(), costs.end())) << shards;
  }
}

ValidationModel sphereModel(const std::string& name, double radiusMm) {
  ValidationModel m;
  m.name = name;
  m.mesh = test::makeSphere(radiusMm, 48, 24);
  return m;
}

TEST(CaseGroups, RunOrderAndVoxelsEstimatedFromTheVolume) {
  const std::vector<ValidationModel> models{sphereModel("small", 5.0), sphereModel("large", 10.0)};
  ValidationOptions options;
  options.voxelSizesMm = {1.0, 2.0};
  const std::vector<CaseGroup> groups = caseGroups(models, options);
  ASSERT_EQ(groups.size(), 4u);
  EXPECT_EQ(groups[0].model, 0u);
  EXPECT_EQ(groups[1].model, 0u);
  EXPECT_EQ(groups[2].model, 1u);
  EXPECT_EQ(groups[1].voxelSizeMm, 2.0);
  // Voxels go as the enclosed volume over the voxel's: 8x fewer at twice the size, 8x more for
  // twice the radius; the cost is the four cases' worth of them.
  EXPECT_NEAR(groups[0].estimatedVoxels / groups[1].estimatedVoxels, 8.0, 1e-9);
  EXPECT_NEAR(groups[2].estimatedVoxels / groups[0].estimatedVoxels, 8.0, 0.05);
  EXPECT_NEAR(groups[0].estimatedVoxels, 4.0 / 3.0 * 3.14159265 * 125.0, 0.02 * 524.0);
  EXPECT_DOUBLE_EQ(groups[3].cost, 4 * groups[3].estimatedVoxels);

  const std::vector<std::string> keys = caseKeys(models, groups);
  ASSERT_EQ(keys.size(), 16u);
  EXPECT_EQ(keys[0], "small|1|crackfree|static");
  EXPECT_EQ(keys[1], "small|1|crackfree|dynamic");
  EXPECT_EQ(keys[2], "small|1|naive|static");
  EXPECT_EQ(keys[7], "small|2|naive|dynamic");
  EXPECT_EQ(keys[15], "large|2|naive|dynamic");
  EXPECT_EQ(caseKey("m.stl", 0.72, "crackfree", "static"), "m.stl|0.72|crackfree|static");
}

// A shard's groups give the cases the whole run gives for them, in caseKeys' order.
TEST(RunValidation, RunsOnlyTheGroupsAsked) {
  const std::vector<ValidationModel> models{sphereModel("a", 6.0), sphereModel("b", 8.0)};
  ValidationOptions options;
  options.voxelSizesMm = {2.0, 3.0};
  options.crackPixels = 64;
  options.drill = false;  // spheres have no humeral head anyway
  const ValidationReport whole = runValidation(models, options);
  ASSERT_EQ(whole.cases.size(), 16u);
  options.groups = std::vector<std::size_t>{1, 2};
  const ValidationReport part = runValidation(models, options);
  ASSERT_EQ(part.cases.size(), 8u);
  const std::vector<std::string> keys = caseKeys(models, caseGroups(models, options));
  for (std::size_t i = 0; i < part.cases.size(); ++i) {
    const ValidationCase& p = part.cases[i];
    const ValidationCase& w = whole.cases[4 + i];
    EXPECT_EQ(caseKey(p.model, p.voxelSizeMm, geometry::surfaceMethodName(p.method),
                      forceModeName(p.mode)),
              keys[4 + i]);
    EXPECT_EQ(p.voxels, w.voxels);
    EXPECT_EQ(p.triangles, w.triangles);
    EXPECT_EQ(p.before.topology.borderEdges, w.before.topology.borderEdges);
    EXPECT_EQ(p.cracks.red, w.cracks.red);
    EXPECT_EQ(p.failures, w.failures);
  }
  EXPECT_EQ(part.cases[0].model, "a");
  EXPECT_EQ(part.cases[0].voxelSizeMm, 3.0);
  EXPECT_EQ(part.cases[4].model, "b");
  EXPECT_EQ(part.cases[4].voxelSizeMm, 2.0);
  options.groups = std::vector<std::size_t>{};
  EXPECT_TRUE(runValidation(models, options).cases.empty());
}

}  // namespace
}  // namespace osteon::validation
