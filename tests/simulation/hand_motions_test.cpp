// The motions of a hand beyond the seed's straight paths (motions.h): the push into intact
// bone with the drill off, then on, and a tremor on a portal path; and the tremor path run
// through the proxy coupling at dynamic 1.2 mm / 2 levels against static 0.3 mm.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "osteon/simulation/motions.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {
namespace {

// The level -2 fills only where refinement needs them (they cost seconds at 0.3 mm).
std::shared_ptr<const BoneModel> bone(double voxelMm, bool refined = true) {
  return BoneModel::open("default", 1.0, voxelMm, {}, refined);
}

const Session& session12() {
  static const Session s = [] {
    SessionOptions o;
    o.keepSurface = false;
    return Session(bone(1.2), o);
  }();
  return s;
}

double angleDeg(const glm::dvec3& u, const glm::dvec3& v) {
  return std::acos(std::clamp(glm::dot(glm::normalize(u), glm::normalize(v)), -1.0, 1.0)) * 180.0 /
         M_PI;
}

TEST(HandMotions, AnIntactPushGoesTenMillimetresPastTheSurfaceWithTheDrillOffThenOn) {
  const PortalPlan plan = session12().portalPath(Portal::FiveOClock);
  const IntactPushOptions o;
  const DrillPath path = intactPushPath(plan, o);
  EXPECT_DOUBLE_EQ(path.durationS(), 7.0);
  const glm::dvec3 in = -plan.normal;
  ToolPose pose;
  bool on = true;
  path.sample(0.0, pose, on);
  EXPECT_FALSE(on);
  EXPECT_NEAR(glm::length(pose.tipMm - (plan.entryMm - 6.0 * in)), 0.0, 1e-9);
  EXPECT_NEAR(angleDeg(pose.forward(), in), 0.0, 1e-6);
  path.sample(0.5, pose, on);
  EXPECT_NEAR(glm::dot(pose.tipMm - plan.entryMm, in), 2.0, 1e-9);  // halfway, at constant speed
  path.sample(1.0, pose, on);
  EXPECT_NEAR(glm::length(pose.tipMm - (plan.entryMm + 10.0 * in)), 0.0, 1e-9);
  for (const double t : {1.0, 3.0, 4.999, 5.0}) {
    path.sample(t, pose, on);
    EXPECT_FALSE(on) << t;
  }
  for (const double t : {5.001, 6.0, 7.0}) {
    path.sample(t, pose, on);
    EXPECT_TRUE(on) << t;
    EXPECT_NEAR(glm::length(pose.tipMm - (plan.entryMm + 10.0 * in)), 0.0, 1e-9);
  }
}

TEST(HandMotions, ATremorIsBoundedFixedBySeedAndKeepsTheDrillState) {
  const DrillPath base = session12().portalPath(Portal::FiveOClock).path;
  const TremorOptions o;
  const DrillPath a = tremorPath(base, o), b = tremorPath(base, o);
  ASSERT_EQ(a.points().size(), b.points().size());
  for (std::size_t i = 0; i < a.points().size(); ++i) {
    ASSERT_EQ(a.points()[i].tipMm, b.points()[i].tipMm);
    ASSERT_EQ(a.points()[i].orientation, b.points()[i].orientation);
  }
  TremorOptions other = o;
  other.seed = 7;
  const DrillPath c = tremorPath(base, other);
  EXPECT_NE(a.points()[100].tipMm, c.points()[100].tipMm);

  double peakMm = 0.0, peakDeg = 0.0;
  for (double t = 0.0; t <= base.durationS(); t += 0.001) {
    ToolPose p, q;
    bool onP = false, onQ = false;
    base.sample(t, p, onP);
    a.sample(t, q, onQ);
    EXPECT_EQ(onP, onQ);
    const glm::dvec3 d = q.tipMm - p.tipMm;
    for (int k = 0; k < 3; ++k) peakMm = std::max(peakMm, std::abs(d[k]));
    peakDeg = std::max(peakDeg, angleDeg(p.forward(), q.forward()));
  }
  // At most 0.3 mm per axis and 3 degrees about each of two axes (sqrt 2 x 3 together), and
  // most of it reached within 7 s.
  EXPECT_LE(peakMm, o.amplitudeMm + 1e-9);
  EXPECT_GT(peakMm, 0.5 * o.amplitudeMm);
  EXPECT_LE(peakDeg, std::sqrt(2.0) * o.amplitudeDeg + 1e-6);
  EXPECT_GT(peakDeg, 0.5 * o.amplitudeDeg);
}

struct TremorRun {
  RunSummary summary;
  double maxStepAtS = 0.0;
};

TremorRun tremorRun(double voxelMm, int levels) {
  SessionOptions o;
  o.levels = levels;
  o.keepSurface = false;
  o.coupling = CouplingMode::Proxy;
  Session s(bone(voxelMm, levels > 0), o);
  const RunResult r = s.run(tremorPath(s.portalPath(Portal::FiveOClock).path));
  TremorRun t;
  t.summary = r.summary;
  double prev = 0.0, best = -1.0;
  for (const ForceLogRow& row : r.log) {
    EXPECT_TRUE(std::isfinite(row.magnitudeN));
    EXPECT_LE(row.magnitudeN, s.simulation().tool().maxForceN + 1e-9);
    if (std::abs(row.magnitudeN - prev) > best) {
      best = std::abs(row.magnitudeN - prev);
      t.maxStepAtS = row.tS;
    }
    prev = row.magnitudeN;
  }
  std::printf(
      "tremor on portal-5, proxy, %g mm / %d levels: max 1 ms step %.4f N (at %.3f s), jitter %.4f "
      "N, largest "
      "gap %.3f mm, steps at clamp %llu, refinement deferred %llu steps\n",
      voxelMm, levels, r.summary.maxStepChangeN, t.maxStepAtS, r.summary.jitterN,
      r.summary.maxGapMm, (unsigned long long)r.summary.clampSteps,
      (unsigned long long)r.summary.totals.stepsDeferred);
  return t;
}

// Under proxy coupling the tremored portal-5 path at dynamic 1.2 mm / 2 levels feels as static
// 0.3 mm does: jitter within 1.25x of it, and a 1 ms step no larger and under 0.1 N (the spring's
// anchor follows the proxy at a bounded speed also as the proxy catches up with the command;
// set onto it at once, the spring's force dropped 0.38 N in one step).
TEST(HandMotions, ATremorThroughTheProxyFeelsAsStaticFineBoneDoes) {
  const TremorRun fine = tremorRun(0.3, 0);
  const TremorRun dynamic = tremorRun(1.2, 2);
  EXPECT_EQ(dynamic.summary.coupling, CouplingMode::Proxy);
  EXPECT_GT(fine.summary.jitterN, 0.0);
  EXPECT_LE(dynamic.summary.jitterN, 1.25 * fine.summary.jitterN);
  EXPECT_LE(dynamic.summary.maxStepChangeN, 1.25 * fine.summary.maxStepChangeN);
  EXPECT_LE(dynamic.summary.maxStepChangeN, 0.1);
  // The proxy follows the hand: a tremor of 0.3 mm leaves it at most about as far behind.
  EXPECT_LT(dynamic.summary.maxGapMm, 1.0);
  EXPECT_GT(dynamic.summary.removedVolumeMm3, 1.0);
  EXPECT_EQ(dynamic.summary.totals.nonFiniteForces, 0u);
}

}  // namespace
}  // namespace osteon::simulation
