// The motions the benchmarks and tests drive the step with (motions.h, and a portal path's
// tilt): where they put the tool.
#include "osteon/simulation/motions.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "osteon/simulation/session.h"

namespace osteon::simulation {
namespace {

const Session& session() {
  static const Session s = [] {
    SessionOptions o;
    o.keepSurface = false;
    return Session(BoneModel::open("default", 1.0, 1.2), o);
  }();
  return s;
}

double angleDeg(const glm::dvec3& u, const glm::dvec3& v) {
  return std::acos(std::clamp(glm::dot(glm::normalize(u), glm::normalize(v)), -1.0, 1.0)) * 180.0 /
         M_PI;
}

// The tip follows the untilted path; the tool turns about it by the tilt, towards the inward
// normal for positive tilts.
TEST(Motions, ATiltTurnsTheToolAboutItsTip) {
  const PortalPlan straight = session().portalPath(Portal::FiveOClock);
  for (const double tilt : {-75.0, -40.0, 20.0, 60.0, 75.0}) {
    SCOPED_TRACE(tilt);
    PortalPathOptions o;
    o.tiltDeg = tilt;
    const PortalPlan tilted = session().portalPath(Portal::FiveOClock, o);
    for (const double t : {0.0, 2.5, 7.0}) {
      ToolPose a, b;
      bool onA = false, onB = false;
      straight.path.sample(t, a, onA);
      tilted.path.sample(t, b, onB);
      EXPECT_EQ(a.tipMm, b.tipMm);
      EXPECT_EQ(onA, onB);
      EXPECT_NEAR(angleDeg(a.forward(), b.forward()), std::abs(tilt), 1e-9);
      // Turned in the plane of travel and the normal, its tip towards -normal when positive.
      EXPECT_NEAR(glm::dot(b.forward(), glm::cross(straight.normal, straight.direction)), 0.0,
                  1e-12);
      const double towardsInward = glm::dot(b.forward() - a.forward(), -straight.normal);
      EXPECT_EQ(towardsInward > 0.0, tilt > 0.0);
    }
  }
  // No tilt: the path as it was, bit for bit (the seed's runs).
  PortalPathOptions zero;
  zero.tiltDeg = 0.0;
  const PortalPlan same = session().portalPath(Portal::FiveOClock, zero);
  EXPECT_EQ(same.path.points().front().orientation, straight.path.points().front().orientation);
}

TEST(Motions, ALateralSweepShavesSideToSideAtTheEntry) {
  const PortalPlan plan = session().portalPath(Portal::SevenOClock);
  const LateralSweepOptions o;
  const DrillPath path = lateralSweepPath(plan, o);
  EXPECT_DOUBLE_EQ(path.durationS(), o.durationS);
  const glm::dvec3 side = glm::normalize(glm::cross(plan.normal, plan.direction));
  double lo = 0.0, hi = 0.0;
  for (double t = 0.0; t <= o.durationS; t += 0.001) {
    ToolPose pose;
    bool on = false;
    path.sample(t, pose, on);
    EXPECT_TRUE(on);
    const double across = glm::dot(pose.tipMm - plan.entryMm, side);
    lo = std::min(lo, across);
    hi = std::max(hi, across);
    if (t > o.reachS) {
      const double depth = glm::dot(plan.entryMm - pose.tipMm, plan.normal);
      EXPECT_NEAR(depth, o.startDepthMm + o.sinkMmPerS * (t - o.reachS), 1e-3);
    }
  }
  EXPECT_NEAR(lo, -o.amplitudeMm, 0.01);
  EXPECT_NEAR(hi, o.amplitudeMm, 0.01);
}

TEST(Motions, AFastPushGoesInAndHolds) {
  const PortalPlan plan = session().portalPath(Portal::FiveOClock);
  FastPushOptions o;
  o.pushS = 0.001;
  const DrillPath path = fastPushPath(plan, o);
  ToolPose before, after;
  bool on = false;
  path.sample(o.holdS, before, on);
  path.sample(o.holdS + o.pushS, after, on);
  EXPECT_EQ(before.tipMm, plan.path.points().front().tipMm);
  EXPECT_NEAR(glm::length(after.tipMm - (plan.entryMm + o.depthMm * plan.direction)), 0.0, 1e-9);
  ToolPose end;
  path.sample(o.durationS, end, on);
  EXPECT_EQ(end.tipMm, after.tipMm);
}

}  // namespace
}  // namespace osteon::simulation
