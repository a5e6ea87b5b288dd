#include "osteon/simulation/drilling.h"

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

using geometry::DynamicProximityHierarchy;
using geometry::VoxelGrid;

// Volume of the part of a ball of radius r beyond a plane at distance h from its centre.
double capVolume(double r, double h) {
  if (h >= r) return 0.0;
  return M_PI * (r - h) * (r - h) * (2.0 * r + h) / 3.0;
}

// A bone slab, top face z = 0, voxel faces on the plane.
struct Slab {
  VoxelGrid grid;
  DynamicProximityHierarchy hierarchy;
  explicit Slab(double voxelMm) {
    geometry::VoxelizeOptions o;
    o.voxelSizeMm = voxelMm;
    grid = geometry::voxelize(test::makeBox({-8, -8, -8}, {8, 8, 0}), o);
    hierarchy = DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
  }
};

TEST(Tool, ShellsAndTheSeedsMaximumCount) {
  const Tool drill = makeTool(ToolKind::Drill, ToolOptions{}, 0.3);
  ASSERT_EQ(drill.partCount, 2);
  const ToolPart& tip = drill.parts[0];
  EXPECT_DOUBLE_EQ(tip.innerRadiusMm, 1.46);
  EXPECT_DOUBLE_EQ(tip.outerRadiusMm, 1.46 + 0.6);
  EXPECT_TRUE(tip.cuts);
  EXPECT_FALSE(drill.parts[1].cuts);
  EXPECT_LE(drill.parts[1].outerRadiusMm, tip.innerRadiusMm);  // the shaft fits its hole
  // Eq. (2): c, the finest voxels the sphere's shell holds, and as the seed prints it.
  const double seedC = (std::pow(2.06, 3) - std::pow(1.46, 3)) / std::pow(0.3, 3);
  EXPECT_NEAR(ForceModel(drill, 0.3, 1.2).maxCount(0), 4.0 / 3.0 * M_PI * seedC, 1e-9);
  ToolOptions literal;
  literal.literalSeedCount = true;
  EXPECT_NEAR(ForceModel(makeTool(ToolKind::Drill, literal, 0.3), 0.3, 1.2).maxCount(0), seedC,
              1e-9);
  const Tool shaver = makeTool(ToolKind::Shaver, ToolOptions{}, 0.3);
  EXPECT_TRUE(shaver.parts[0].cutsOnSideOnly);
  EXPECT_GT(shaver.parts[0].lengthMm(), 0.0);
  ToolOptions custom;
  custom.outerRadiusMm = 2.5;
  EXPECT_DOUBLE_EQ(makeTool(ToolKind::Burr, custom, 0.3).parts[0].outerRadiusMm, 2.5);
}

TEST(Tool, BadOptionsAreInputErrors) {
  EXPECT_THROW(parseToolKind("scalpel"), InputError);
  ToolOptions o;
  o.tipDiameterMm = -1.0;
  EXPECT_THROW(validateToolOptions(o), InputError);
  o = ToolOptions{};
  o.outerRadiusMm = 1.0;  // inside the 1.46 mm inner layer
  EXPECT_THROW(validateToolOptions(o), InputError);
  o = ToolOptions{};
  o.shaftDiameterMm = 3.0;
  EXPECT_THROW(validateToolOptions(o), InputError);
  DrillingOptions d;
  d.levels = 3;
  EXPECT_THROW(validateDrillingOptions(d), InputError);
}

TEST(Tool, PosePointsTheToolWhereAsked) {
  for (const glm::dvec3 f : {glm::dvec3(0, 0, -1), glm::dvec3(0, 0, 1), glm::dvec3(1, 2, -3)}) {
    const ToolPose pose = ToolPose::pointing({1, 2, 3}, f);
    EXPECT_NEAR(glm::length(pose.forward() - glm::normalize(f)), 0.0, 1e-12);
    EXPECT_NEAR(glm::length(pose.toWorld({0, 0, 0}) - glm::dvec3(1, 2, 3)), 0.0, 1e-12);
  }
}

// Eqs. (1)-(2) on a flat slab: the force points out of the slab and n is the bone in the
// shell, counted exactly over the voxels and close to the analytic cap volumes.
TEST(Contact, SlabAtKnownDepthGivesTheExpectedCountAndDirection) {
  for (const int levels : {0, 2}) {
    Slab slab(levels == 0 ? 0.25 : 1.0);
    DrillingOptions options;
    options.levels = levels;
    DrillingSimulation sim(slab.grid, slab.hierarchy, nullptr, ToolKind::Burr, ToolOptions{},
                           options);
    ASSERT_DOUBLE_EQ(sim.finestVoxelMm(), 0.25);
    const ToolPart& tip = sim.tool().parts[0];
    const double h = 1.0;  // tool centre 1 mm above the slab: the tip is 0.46 mm deep
    const glm::dvec3 centre(0.13, -0.21, h);
    const ToolPose pose = ToolPose::pointing(centre, {0, 0, -1});
    const StepOutput out = sim.step({0.0, pose, false});
    EXPECT_EQ(out.contact.level, -levels);
    // The samples a check can list (nothing was removed) are the ones the force counted.
    const std::vector<geometry::VoxelSample> shell =
        sim.forceModel().shellSamples(sim.voxels(), pose, 0);
    EXPECT_EQ(shell.size(), out.contact.samples) << "levels " << levels;
    for (const geometry::VoxelSample& s : shell) {
      const double d = glm::length(s.centreMm - centre);
      EXPECT_TRUE(d > tip.innerRadiusMm && d <= tip.outerRadiusMm) << d;
    }
    // Exact: every finest voxel of the slab whose centre lies in the shell.
    const double v = 0.25;
    double expected = 0.0;
    for (double z = -8 + v / 2; z < 0; z += v)
      for (double y = -8 + v / 2; y < 8; y += v)
        for (double x = -8 + v / 2; x < 8; x += v) {
          const double d = glm::length(glm::dvec3(x, y, z) - centre);
          if (d > tip.innerRadiusMm && d <= tip.outerRadiusMm) expected += 1.0;
        }
    EXPECT_NEAR(out.contact.contactVoxels, expected, 1e-6) << "levels " << levels;
    const double analytic =
        (capVolume(tip.outerRadiusMm, h) - capVolume(tip.innerRadiusMm, h)) / (v * v * v);
    EXPECT_NEAR(out.contact.contactVoxels, analytic, 0.05 * analytic) << "levels " << levels;
    const double c = sim.forceModel().maxCount(0);
    EXPECT_NEAR(out.contact.magnitudeN, std::min(3.3 * expected / c, 3.3), 1e-9);
    const glm::dvec3 dir = out.contact.forceN / out.contact.magnitudeN;
    EXPECT_GT(dir.z, std::cos(2.0 * M_PI / 180.0)) << "levels " << levels;
  }
}

TEST(Contact, NoBoneNoForceAndBrokenPosesAreCounted) {
  Slab slab(0.5);
  DrillingSimulation sim(slab.grid, slab.hierarchy, nullptr, ToolKind::Drill, ToolOptions{},
                         DrillingOptions{});
  const StepOutput far = sim.step({0.0, ToolPose::pointing({0, 0, 20}, {0, 0, -1}), true});
  EXPECT_EQ(far.contact.magnitudeN, 0.0);
  EXPECT_EQ(far.removal.removedFill, 0u);
  const StepOutput nan = sim.step({0.001, ToolPose::pointing({NAN, 0, 1}, {0, 0, -1}), true});
  EXPECT_TRUE(nan.contact.nonFinite);
  EXPECT_EQ(nan.contact.magnitudeN, 0.0);
  EXPECT_EQ(sim.totals().nonFiniteForces, 1u);
}

// Seed 3.5: each drilling step takes one unit of d; a sample goes at d <= 0, not before.
TEST(Removal, DensityWearsDownInExactlyDSteps) {
  for (const int levels : {0, 1}) {
    Slab slab(0.5);
    const glm::ivec3 d = slab.grid.dims();
    for (int z = 0; z < d.z; ++z)
      for (int y = 0; y < d.y; ++y)
        for (int x = 0; x < d.x; ++x) {
          if (slab.grid.fill({x, y, z}) > 0) slab.grid.set({x, y, z}, slab.grid.fill({x, y, z}), 7);
        }
    DrillingOptions options;
    options.levels = levels;
    DrillingSimulation sim(slab.grid, slab.hierarchy, nullptr, ToolKind::Burr, ToolOptions{},
                           options);
    const ToolPose pose = ToolPose::pointing({0.1, 0.1, 0.5}, {0, 0, -1});
    const std::uint64_t before = slab.grid.totalFill();
    for (int step = 1; step <= 7; ++step) {
      const StepOutput out = sim.step({0.001 * step, pose, true});
      if (step < 7) {
        EXPECT_EQ(out.removal.samplesRemoved, 0u) << "step " << step << " levels " << levels;
        EXPECT_GT(out.removal.samplesDecremented, 0u);
      } else {
        EXPECT_GT(out.removal.samplesRemoved, 0u) << "levels " << levels;
        EXPECT_EQ(out.removal.samplesDecremented, 0u);
      }
    }
    EXPECT_EQ(slab.grid.totalFill(), before - sim.totals().removedFill);
    EXPECT_GT(sim.removedVolumeMm3(), 0.0);
  }
}

// A long cut at a fine voxel size reaches far more voxels than the default room for a query:
// every voxel in the cut goes in one step all the same (none left silently).
TEST(Removal, AShaverInsideBoneAtFineVoxelsRemovesEveryVoxelInItsCut) {
  Slab slab(0.2);
  DrillingOptions options;
  options.levels = 0;
  options.decrement = 1000;  // every density gone in one step
  DrillingSimulation sim(slab.grid, slab.hierarchy, nullptr, ToolKind::Shaver, ToolOptions{},
                         options);
  const ToolPose pose = ToolPose::pointing({0.05, -0.1, -4.0}, {1, 0.2, 0});
  const StepOutput out = sim.step({0.0, pose, true});
  EXPECT_EQ(sim.totals().cutOverflows, 0u);
  const Tool& tool = sim.tool();
  std::size_t inCut = 0, left = 0;
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    if (!part.cuts) continue;
    const CutVolume cut{pose.toWorld(part.aMm), pose.toWorld(part.bMm), part.innerRadiusMm,
                        part.cutsOnSideOnly};
    const glm::ivec3 dims = slab.grid.dims();
    for (int z = 0; z < dims.z; ++z)
      for (int y = 0; y < dims.y; ++y)
        for (int x = 0; x < dims.x; ++x) {
          if (!cut.contains(slab.grid.voxelCentreMm({x, y, z}))) continue;
          ++inCut;
          left += slab.grid.fill({x, y, z}) != 0 ? 1u : 0u;
        }
  }
  // The cut's query (its bounding sphere, 3.46 mm) holds about 21,000 voxels here, five times
  // the 4,096 a query held before.
  EXPECT_GT(inCut, 3000u);
  EXPECT_EQ(left, 0u);
  EXPECT_EQ(out.removal.voxelsEmptied, inCut);
}

// The built-in humerus drilled along a straight line, dynamic and static: every unit of fill
// that leaves the grid is accounted for, forces stay within N_max, and a second run gives the
// same forces bit for bit.
class HumerusDrilling : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = new geometry::HumerusModel(geometry::buildHumerusModel());
  }
  static void TearDownTestSuite() { delete model_; }

  std::vector<double> run(int levels, std::uint64_t* removed = nullptr, bool* conserved = nullptr,
                          double querySkinVoxels = DrillingOptions{}.querySkinVoxels,
                          ToolKind kind = ToolKind::Drill) {
    geometry::VoxelizeOptions o;
    o.voxelSizeMm = 1.2;
    VoxelGrid grid = geometry::voxelize(model_->mesh, o);
    DynamicProximityHierarchy hierarchy =
        DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
    const std::uint64_t before = grid.totalFill();
    DrillingOptions options;
    options.levels = levels;
    options.querySkinVoxels = querySkinVoxels;
    DrillingSimulation sim(grid, hierarchy, nullptr, kind, ToolOptions{}, options);
    const glm::dvec3 axis = model_->headAxis;
    const glm::dvec3 start = model_->headCentreMm + axis * (model_->headRadiusMm + 3.0);
    std::vector<double> forces;
    for (int i = 0; i < 3000; ++i) {
      const double t = 0.001 * i;
      const glm::dvec3 tip = start - axis * (5.0 * t);  // 5 mm/s into the head
      const StepOutput out = sim.step({t, ToolPose::pointing(tip, -axis), true});
      forces.push_back(out.contact.forceN.x);
      forces.push_back(out.contact.forceN.y);
      forces.push_back(out.contact.forceN.z);
      EXPECT_LE(out.contact.magnitudeN, 3.3 + 1e-12);
    }
    EXPECT_EQ(sim.totals().brickAllocations, 0u);  // the spare pool covered every new brick
    if (removed) *removed = sim.totals().removedFill;
    if (conserved) *conserved = grid.totalFill() == before - sim.totals().removedFill;
    return forces;
  }

  static geometry::HumerusModel* model_;
};
geometry::HumerusModel* HumerusDrilling::model_ = nullptr;

TEST_F(HumerusDrilling, RemovalConservesVolumeAndRunsAreBitIdentical) {
  for (const int levels : {0, 2}) {
    std::uint64_t removed = 0;
    bool conserved = false;
    const std::vector<double> a = run(levels, &removed, &conserved);
    EXPECT_GT(removed, 0u) << "levels " << levels;
    EXPECT_TRUE(conserved) << "levels " << levels;
    const std::vector<double> b = run(levels);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << "levels " << levels;
    double peak = 0.0;
    for (std::size_t i = 0; i < a.size(); i += 3)
      peak = std::max(peak, std::hypot(a[i], a[i + 1], a[i + 2]));
    EXPECT_GT(peak, 0.5) << "levels " << levels;  // the drill met bone
  }
}

// The hierarchy queries answered from their caches (the default) give the forces and the
// removal of walking the hierarchy at every step, bit for bit.
TEST_F(HumerusDrilling, CachedQueriesGiveTheForcesOfAWalkEveryStep) {
  ASSERT_GT(DrillingOptions{}.querySkinVoxels, 0.0);
  for (const ToolKind kind : {ToolKind::Drill, ToolKind::Shaver}) {
    for (const int levels : {0, 2}) {
      std::uint64_t removedCached = 0, removedWalked = 0;
      const std::vector<double> cached = run(levels, &removedCached, nullptr, 1.0, kind);
      const std::vector<double> walked = run(levels, &removedWalked, nullptr, 0.0, kind);
      ASSERT_EQ(cached.size(), walked.size());
      EXPECT_EQ(std::memcmp(cached.data(), walked.data(), cached.size() * sizeof(double)), 0)
          << toolKindName(kind) << " levels " << levels;
      EXPECT_EQ(removedCached, removedWalked);
      EXPECT_GT(removedCached, 0u);
    }
  }
}

TEST_F(HumerusDrilling, ForcesStayBoundedAndFiniteOnRandomPoses) {
  geometry::VoxelizeOptions o;
  o.voxelSizeMm = 1.2;
  VoxelGrid grid = geometry::voxelize(model_->mesh, o);
  DynamicProximityHierarchy hierarchy =
      DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
  for (const ToolKind kind : {ToolKind::Drill, ToolKind::Burr, ToolKind::Shaver}) {
    DrillingSimulation sim(grid, hierarchy, nullptr, kind, ToolOptions{}, DrillingOptions{});
    std::mt19937 rng(1234);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double r = model_->headRadiusMm + 4.0;
    for (int i = 0; i < 1500; ++i) {
      const glm::dvec3 tip = model_->headCentreMm + r * glm::dvec3(u(rng), u(rng), u(rng));
      const StepOutput out =
          sim.step({0.001 * i, ToolPose::pointing(tip, {u(rng), u(rng), u(rng)}), i % 2 == 0});
      ASSERT_TRUE(std::isfinite(out.contact.magnitudeN));
      ASSERT_LE(out.contact.magnitudeN, 3.3 + 1e-12);
      ASSERT_FALSE(out.contact.nonFinite);
    }
    EXPECT_EQ(sim.totals().nonFiniteForces, 0u) << toolKindName(kind);
  }
}

// A hierarchy with no root (an empty grid) answers every query with nothing: no force, no
// removal, no crash, at every level of refinement.
TEST(Drilling, AnEmptyGridGivesNoForceAndNoCrash) {
  const geometry::TriangleMesh box = test::makeBox({0, 0, 0}, {10, 10, 10});
  VoxelGrid grid = geometry::makeGridFor(box, 1.0);
  DynamicProximityHierarchy hierarchy =
      DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
  ASSERT_EQ(hierarchy.voxelCount(), 0u);
  const geometry::EmbreeScene scene(box);
  const geometry::FineFillSource source = geometry::FineFillSource::sample(grid, box, scene);
  for (const int levels : {0, 1, 2}) {
    DrillingOptions options;
    options.levels = levels;
    DrillingSimulation sim(grid, hierarchy, levels > 0 ? &source : nullptr, ToolKind::Drill,
                           ToolOptions{}, options);
    for (int i = 0; i < 50; ++i) {
      const StepOutput out =
          sim.step({0.001 * i, ToolPose::pointing({5, 5, 12.0 - 0.2 * i}, {0, 0, -1}), true});
      EXPECT_EQ(out.contact.magnitudeN, 0.0);
    }
    EXPECT_EQ(sim.totals().samplesRemoved, 0u) << "levels " << levels;
  }
}

}  // namespace
}  // namespace osteon::simulation
