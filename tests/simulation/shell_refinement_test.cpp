// Refinement wherever bone touches a part (the drill's shaft too), and its per-step budget:
// a tilted drill on the built-in bone, through BoneModel::open and Session as the CLI drives
// them.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "osteon/simulation/experiment.h"
#include "osteon/simulation/motions.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {
namespace {

std::shared_ptr<const BoneModel> bone(double voxelMm) {
  // 0.3 mm is only run static: it needs no fine fills.
  static const std::shared_ptr<const BoneModel> coarse = BoneModel::open("default", 1.0, 1.2);
  static const std::shared_ptr<const BoneModel> fine =
      BoneModel::open("default", 1.0, 0.3, {}, false);
  return voxelMm == 1.2 ? coarse : fine;
}

SessionOptions optionsFor(int levels, bool refineShells = true,
                          std::size_t budget = DrillingOptions{}.refineBudgetVoxels) {
  SessionOptions o;
  o.levels = levels;
  o.keepSurface = false;
  o.drilling.refineShells = refineShells;
  o.drilling.refineBudgetVoxels = budget;
  return o;
}

RunResult tilted(double voxelMm, const SessionOptions& options, Portal portal, double tiltDeg,
                 DrillingTotals* totals = nullptr) {
  Session session(bone(voxelMm), options);
  PortalPathOptions po;
  po.tiltDeg = tiltDeg;
  RunResult r = session.run(session.portalPath(portal, po).path);
  if (totals) *totals = session.totals();
  return r;
}

// The shaft levered against the hole's rim and wall (positive tilts) or laid into the bone
// (negative): with 1.2 mm voxels and 2 levels the force is static 0.3 mm's (the same finest
// samples where any part touches bone), where refining around the cutting part alone let the
// shaft push with 1.2 mm voxels (steps of 0.5-0.9 N).
TEST(ShellRefinement, ATiltedShaftPushesWithTheFinestSamples) {
  for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
    for (const double tilt : {40.0, 60.0, -40.0, -60.0}) {
      SCOPED_TRACE(std::string(portalName(portal)) + " tilted " + std::to_string(tilt));
      const RunSummary fine = tilted(0.3, optionsFor(0), portal, tilt).summary;
      const RunSummary dynamic = tilted(1.2, optionsFor(2), portal, tilt).summary;
      const RunSummary coarse = tilted(1.2, optionsFor(0), portal, tilt).summary;
      EXPECT_LE(dynamic.maxStepChangeN, 0.1);
      EXPECT_LE(dynamic.jitterN, 1.25 * fine.jitterN);
      EXPECT_GT(dynamic.maxForceN, 0.5);  // the run does push on bone
      // The path is one where base voxels do not do (else the test shows nothing).
      EXPECT_GT(coarse.maxStepChangeN, 0.3);
      EXPECT_EQ(dynamic.totals.refinePoolExhausted, 0u);
    }
  }
}

// The seed's refinement (around the cutting parts only) stays available and is what the
// shell refinement changes on a tilted path.
TEST(ShellRefinement, CuttingPartsAloneLeaveTheShaftCoarse) {
  const RunSummary seed = tilted(1.2, optionsFor(2, false), Portal::FiveOClock, 60.0).summary;
  EXPECT_GT(seed.maxStepChangeN, 0.3);
}

// A budget of one voxel per step: the shell's refinement is spread over later steps (and
// counted), the removal is the same, and the force steps no more than without the budget.
TEST(ShellRefinement, ABudgetDefersRefinementWithoutAForceStep) {
  for (const double tilt : {60.0, 75.0}) {
    SCOPED_TRACE(tilt);
    DrillingTotals free, tight;
    const RunSummary unbounded =
        tilted(1.2, optionsFor(2, true, 0), Portal::FiveOClock, tilt, &free).summary;
    const RunSummary budgeted =
        tilted(1.2, optionsFor(2, true, 1), Portal::FiveOClock, tilt, &tight).summary;
    EXPECT_EQ(free.stepsDeferred, 0u);
    EXPECT_GT(tight.stepsDeferred, 0u);
    EXPECT_GE(tight.voxelsDeferred, tight.stepsDeferred);
    EXPECT_EQ(tight.removedFill, free.removedFill);
    EXPECT_LE(budgeted.maxStepChangeN, unbounded.maxStepChangeN + 1e-9);
    EXPECT_LE(budgeted.maxStepChangeN, 0.1);
  }
}

}  // namespace
}  // namespace osteon::simulation
