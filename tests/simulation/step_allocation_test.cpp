// The drilling step allocates nothing, whatever the pose and motion: a tilted shaft refining
// the bone it touches (with and without a refinement budget that defers), lateral shaving
// sweeps with each tool, a fast push. Its own program, as it counts every heap allocation.
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <string>

#include <gtest/gtest.h>

#include "osteon/simulation/motions.h"
#include "osteon/simulation/session.h"
#include "support/allocation_counter.h"

namespace osteon::simulation {
namespace {

const std::shared_ptr<const BoneModel>& bone() {
  static const std::shared_ptr<const BoneModel> b = BoneModel::open("default", 1.0, 1.2);
  return b;
}

// Heap allocations made by DrillingSimulation::step over the whole path, at 1 kHz.
std::uint64_t allocationsInSteps(Session& session, const DrillPath& path) {
  DrillingSimulation& sim = session.simulation();
  std::uint64_t inSteps = 0;
  const auto steps = std::size_t(path.durationS() * 1000.0);
  for (std::size_t i = 0; i <= steps; ++i) {
    StepInput in;
    in.tS = double(i) * 0.001;
    path.sample(in.tS, in.pose, in.drillOn);
    const std::uint64_t before = test::allocations();
    sim.step(in);
    inSteps += test::allocations() - before;
  }
  return inSteps;
}

SessionOptions options(ToolKind tool, std::size_t budget) {
  SessionOptions o;
  o.levels = 2;
  o.tool = tool;
  o.keepSurface = false;
  o.drilling.refineBudgetVoxels = budget;
  return o;
}

TEST(StepAllocation, TiltedShaftsWithAndWithoutDeferral) {
  for (const std::size_t budget :
       {std::size_t(0), std::size_t(1), DrillingOptions{}.refineBudgetVoxels}) {
    for (const double tilt : {0.0, 40.0, 75.0}) {
      SCOPED_TRACE("budget " + std::to_string(budget) + ", tilt " + std::to_string(tilt));
      const std::uint64_t beforeSetUp = test::allocations();
      Session session(bone(), options(ToolKind::Drill, budget));
      EXPECT_GT(test::allocations(), beforeSetUp);  // the count does see the set-up's allocations
      PortalPathOptions po;
      po.tiltDeg = tilt;
      const DrillPath path = session.portalPath(Portal::SevenOClock, po).path;
      EXPECT_EQ(allocationsInSteps(session, path), 0u);
      EXPECT_GT(session.totals().removedFill, 0u);
      if (budget == 1 && tilt > 0.0) {
        EXPECT_GT(session.totals().stepsDeferred, 0u);
      }
    }
  }
}

TEST(StepAllocation, LateralSweepsAndAFastPush) {
  for (const ToolKind tool : {ToolKind::Drill, ToolKind::Burr, ToolKind::Shaver}) {
    SCOPED_TRACE(toolKindName(tool));
    Session session(bone(), options(tool, DrillingOptions{}.refineBudgetVoxels));
    const DrillPath path = lateralSweepPath(session.portalPath(Portal::FiveOClock));
    EXPECT_EQ(allocationsInSteps(session, path), 0u);
    EXPECT_GT(session.totals().removedFill, 0u);
  }
  Session session(bone(), options(ToolKind::Drill, DrillingOptions{}.refineBudgetVoxels));
  const DrillPath path = fastPushPath(session.portalPath(Portal::FiveOClock));
  EXPECT_EQ(allocationsInSteps(session, path), 0u);
  EXPECT_GT(session.totals().removedFill, 0u);
}

}  // namespace
}  // namespace osteon::simulation

namespace osteon::simulation {
namespace {

// The calibrated model's haptic step (coupling, feed law, heat deposit) allocates nothing
// either, at every rpm and with irrigation toggling; its heat is conducted outside the steps.
TEST(StepAllocation, TheCalibratedModelsHapticStep) {
  SessionOptions o = options(ToolKind::Drill, DrillingOptions{}.refineBudgetVoxels);
  o.coupling = CouplingMode::Proxy;
  o.forceModel = ForceModelKind::Calibrated;
  Session session(bone(), o);
  ASSERT_NE(session.thermal(), nullptr);
  const DrillPath path = session.portalPath(Portal::FiveOClock).path;
  ProxyCoupling& coupling = *session.coupling();
  std::uint64_t inSteps = 0;
  double maxThrustN = 0.0;
  const auto steps = std::size_t(path.durationS() * 1000.0);
  for (std::size_t i = 0; i <= steps; ++i) {
    StepInput in;
    in.tS = double(i) * 0.001;
    path.sample(in.tS, in.pose, in.drillOn);
    in.settings = {i < steps / 2 ? 800.0 : 2000.0, (i / 500) % 2 == 1};
    const std::uint64_t before = test::allocations();
    const HapticStep h = coupling.step(in);
    inSteps += test::allocations() - before;
    maxThrustN = std::max(maxThrustN, h.thrustRealN);
    if (i % 10 == 0) session.thermal()->diffuse(0.01);
  }
  EXPECT_EQ(inSteps, 0u);
  EXPECT_GT(session.totals().removedFill, 0u);
  EXPECT_GT(maxThrustN, 10.0);
  EXPECT_GT(session.thermal()->peakC(), 37.5);
}

}  // namespace
}  // namespace osteon::simulation
