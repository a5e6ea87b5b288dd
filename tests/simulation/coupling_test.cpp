// The proxy coupling (coupling.h): bone stops the tool, the drill eats its way in, the shaft
// never enters bone, free space leaves the proxy on the command, the force is finite, within
// N_max and settles, and a step allocates nothing. On a slab and on the built-in bone
// (coupling_push_test.cpp: a push into the built-in bone with the drill off, then on).
#include "osteon/simulation/coupling.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "coupling_support.h"
#include "osteon/core/error.h"
#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/motions.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"
#include "support/allocation_counter.h"
#include "support/shapes.h"

namespace osteon::simulation {
namespace {

using test::expectSane;
using test::kMaxN;

// A bone slab, top face z = 0, in a session (the drill, the given levels).
Session slabSession(double voxelMm, int levels) {
  SessionOptions o;
  o.voxelSizeMm = voxelMm;
  o.levels = levels;
  o.keepSurface = false;
  return Session::fromMesh(test::makeBox({-8, -8, -8}, {8, 8, 0}), o, "slab");
}

ToolPose down(const glm::dvec3& tipMm) {
  return ToolPose::pointing(tipMm, {0.0, 0.0, -1.0});
}

TEST(ProxyCoupling, DefaultsAreCriticallyDampedAndValidated) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  EXPECT_DOUBLE_EQ(c.options().stiffnessNPerMm, 0.5);
  // b = 2 sqrt(k m): 2 sqrt(500 N/m x 0.05 kg) = 10 N s/m.
  EXPECT_NEAR(c.dampingNsPerMm(), 0.010, 1e-12);
  EXPECT_GT(c.rotationalDampingNmmSPerRad(), 0.0);
  CouplingOptions bad;
  bad.stiffnessNPerMm = -1.0;
  EXPECT_THROW(validateCouplingOptions(bad), InputError);
  EXPECT_EQ(parseCouplingMode("proxy"), CouplingMode::Proxy);
  EXPECT_EQ(parseCouplingMode("direct"), CouplingMode::Direct);
  EXPECT_THROW(parseCouplingMode("spring"), InputError);
}

TEST(ProxyCoupling, FreeSpaceProxyIsTheCommand) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  for (int i = 0; i < 2000; ++i) {
    const double t = 0.001 * i;
    // Circles and turns 6 mm above the slab, fast (about 190 mm/s).
    const glm::dvec3 tip(5.0 * std::cos(6.0 * t), 5.0 * std::sin(6.0 * t), 6.0 + std::sin(9.0 * t));
    const ToolPose cmd = ToolPose::pointing(tip, {std::sin(3.0 * t), 0.2, -1.0});
    const HapticStep h = c.step({t, cmd, i % 2 == 0});
    ASSERT_EQ(h.proxy.tipMm, cmd.tipMm) << t;
    ASSERT_EQ(h.proxy.orientation, cmd.orientation) << t;
    ASSERT_EQ(h.forceN, glm::dvec3(0.0)) << t;
  }
  EXPECT_EQ(c.totals().maxGapMm, 0.0);
  EXPECT_EQ(s.totals().samplesRemoved, 0u);
}

// The command moves 4 mm into the slab in 200 ms (35 mm/s, a firm push) and is held there
// (drill off).
struct HeldPush {
  std::vector<HapticStep> steps;
  double surfaceDepthMm = 0.0;  // of the proxy's inner layer past z = 0 at the end
};

HeldPush heldPush(Session& s, ProxyCoupling& c, double holdS) {
  HeldPush r;
  const double startZ = 3.0, endZ = -4.0 + 1.46;  // the tip sphere's front 4 mm in
  const int n = int(std::lround((0.2 + holdS) / 0.001));
  for (int i = 0; i <= n; ++i) {
    const double t = 0.001 * i;
    const double z = t < 0.2 ? startZ + (endZ - startZ) * t / 0.2 : endZ;
    r.steps.push_back(c.step({t, down({0.3, -0.2, z}), false}));
    expectSane(r.steps.back());
  }
  r.surfaceDepthMm = -(c.proxy().tipMm.z - s.simulation().tool().parts[0].innerRadiusMm);
  return r;
}

TEST(ProxyCoupling, BoneStopsTheToolWithTheDrillOff) {
  for (int levels : {0, 2}) {
    Session s = slabSession(levels == 0 ? 0.3 : 1.2, levels);
    ProxyCoupling c(s.simulation());
    const HeldPush r = heldPush(s, c, 1.0);
    const ToolPart& tip = s.simulation().tool().parts[0];
    const double cushionMm = tip.outerRadiusMm - tip.innerRadiusMm;
    EXPECT_EQ(s.totals().samplesRemoved, 0u) << levels;
    // The proxy's inner layer is within its cushion of the surface, and not far short of it.
    EXPECT_LE(r.surfaceDepthMm, cushionMm) << levels;
    EXPECT_GE(r.surfaceDepthMm, -cushionMm) << levels;
    EXPECT_EQ(c.boneInsideInnerLayer(c.proxy(), 0), 0.0) << levels;
    // The force pushes the hand back out, k x the gap plus the cushion's contact, at the clamp.
    const HapticStep& last = r.steps.back();
    EXPECT_GT(last.forceN.z, 1.5) << levels;
    EXPECT_GT(last.gapMm, 3.0) << levels;
  }
}

TEST(ProxyCoupling, HeldInBoneSettlesWithin50msWithoutSignChanges) {
  // Soft enough that the force stays under the clamp, where an oscillation would show.
  Session s = slabSession(1.2, 2);
  CouplingOptions o;
  o.stiffnessNPerMm = 0.4;
  ProxyCoupling c(s.simulation(), o);
  const HeldPush r = heldPush(s, c, 0.5);
  const std::size_t holdStart = 200, settled = holdStart + 50;
  const double finalZ = r.steps.back().forceN.z;
  EXPECT_GT(finalZ, 0.5);
  // Settled: from here on within 1 % of the final force.
  std::size_t settledAt = r.steps.size();
  while (settledAt > holdStart &&
         std::abs(r.steps[settledAt - 1].forceN.z - finalZ) <= 0.01 * finalZ)
    --settledAt;
  std::printf("held push: settled %zu ms after the hold began\n", settledAt - holdStart);
  for (std::size_t i = settled; i < r.steps.size(); ++i) {
    // Along the push (z): the same sign, and within 1 % of the final force.
    ASSERT_GT(r.steps[i].forceN.z, 0.0) << i;
    ASSERT_NEAR(r.steps[i].forceN.z, finalZ, 0.01 * finalZ) << i;
  }
  // Continuity at contact onset: no 1 ms step past 0.1 N on the way in and after.
  double maxStepN = 0.0;
  for (std::size_t i = 1; i < r.steps.size(); ++i) {
    maxStepN = std::max(maxStepN, glm::length(r.steps[i].forceN - r.steps[i - 1].forceN));
  }
  std::printf("held push: max 1 ms force step %.4f N, final %.3f N, gap %.3f mm\n", maxStepN,
              finalZ, r.steps.back().gapMm);
  EXPECT_LT(maxStepN, 0.1);
}

// The device and the hand as a mass on two springs: a 50 g stylus held by a relaxed grip
// (0.3 N/mm, lightly damped) whose target goes 3 mm past the slab's surface in 100 ms and
// stays; the rendered force acts on the stylus, whose position is the command. The coupled
// system settles within 50 ms of the hold: no force sign change along the push after it, the
// force within 2 % of its rest value, and the stylus still to a micrometre after 400 ms.
TEST(ProxyCoupling, AHandOnTheStylusSettlesWithoutOscillating) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  const double massKg = 0.05, handNPerMm = 0.3, handNsPerMm = 0.002, dtS = 0.001;
  const double startZ = 3.0, targetZ = 1.46 - 3.0;
  double z = startZ, vMmPerS = 0.0;
  std::vector<double> forceZ, stylusZ;
  for (int i = 0; i <= 600; ++i) {
    const double t = dtS * i;
    const double target = t < 0.1 ? startZ + (targetZ - startZ) * t / 0.1 : targetZ;
    const HapticStep h = c.step({t, down({0.2, 0.1, z}), false});
    expectSane(h);
    forceZ.push_back(h.forceN.z);
    stylusZ.push_back(z);
    // Semi-implicit Euler in mm, N and kg: a [mm/s^2] = F / m x 1000.
    const double handN = handNPerMm * (target - z) - handNsPerMm * vMmPerS;
    vMmPerS += (handN + h.forceN.z) / massKg * 1e3 * dtS;
    z += vMmPerS * dtS;
  }
  const std::size_t settled = 100 + 50;
  const double finalN = forceZ.back();
  EXPECT_GT(finalN, 0.3);
  double swingMm = 0.0;
  for (std::size_t i = settled; i < forceZ.size(); ++i) {
    ASSERT_GT(forceZ[i], 0.0) << i;
    ASSERT_NEAR(forceZ[i], finalN, 0.02 * finalN) << i;
    swingMm = std::max(swingMm, std::abs(stylusZ[i] - stylusZ.back()));
  }
  // What is left dies away: the last 200 ms still to a micrometre (no sustained oscillation).
  double lateSwingMm = 0.0;
  for (std::size_t i = stylusZ.size() - 200; i < stylusZ.size(); ++i) {
    lateSwingMm = std::max(lateSwingMm, std::abs(stylusZ[i] - stylusZ.back()));
  }
  std::printf(
      "hand on the stylus: final %.3f N; stylus within %.4f mm of rest from 50 ms after the hold, "
      "%.5f mm over the last 200 ms\n",
      finalN, swingMm, lateSwingMm);
  EXPECT_LT(swingMm, 0.05);
  EXPECT_LT(lateSwingMm, 0.001);
  EXPECT_EQ(s.totals().samplesRemoved, 0u);
}

TEST(ProxyCoupling, ContinuousAtRelease) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  HapticStep prev = c.step({0.0, down({0.0, 0.0, 2.0}), false});
  double maxStepN = 0.0;
  // 2.5 mm past the slab's surface and back out at 10 mm/s.
  for (int i = 1; i <= 600; ++i) {
    const double t = 0.001 * i;
    const double z = 2.0 - 10.0 * (t < 0.3 ? t : 0.6 - t);
    const HapticStep h = c.step({t, down({0.0, 0.0, z}), false});
    expectSane(h);
    maxStepN = std::max(maxStepN, glm::length(h.forceN - prev.forceN));
    prev = h;
  }
  std::printf("in and out at 10 mm/s: max 1 ms force step %.4f N\n", maxStepN);
  EXPECT_LT(maxStepN, 0.1);
  // Out of the bone: the proxy is the command again, the damping's tail has died away.
  EXPECT_LT(glm::length(prev.forceN), 1e-3);
  EXPECT_EQ(prev.proxy.tipMm, prev.commanded.tipMm);
}

void shaftPushedSideways(double voxelMm, int levels, double sinkMm) {
  // The drill lies along +x, 3 mm above the slab, its tip beyond the slab's edge: the shaft
  // alone meets bone when the command goes down 6 mm, sideways to it.
  Session s = slabSession(voxelMm, levels);
  ProxyCoupling c(s.simulation());
  const ToolPart& shaft = s.simulation().tool().parts[1];
  ASSERT_FALSE(shaft.cuts);
  double lowestAxisZ = 1e9;
  for (int i = 0; i <= 1000; ++i) {
    const double t = 0.001 * i;
    const double z = 3.0 - 6.0 * std::min(1.0, t / 0.5);
    const ToolPose cmd =
        ToolPose::pointing({20.0 + 2.0 * std::sin(4.0 * t), 0.0, z}, {1.0, 0.0, 0.0});
    const HapticStep h = c.step({t, cmd, true});
    expectSane(h);
    ASSERT_EQ(c.boneInsideInnerLayer(h.proxy, 1), 0.0) << t;
    lowestAxisZ = std::min(lowestAxisZ, h.proxy.tipMm.z);
  }
  // The shaft rests on the slab: its inner layer no deeper than the samples it meets allow.
  std::printf("shaft at %.1f mm / %d levels: axis %.3f mm above the slab (radius %.2f)\n", voxelMm,
              levels, lowestAxisZ, shaft.innerRadiusMm);
  EXPECT_GE(lowestAxisZ, shaft.innerRadiusMm - sinkMm);
  EXPECT_GT(c.step({1.001, ToolPose::pointing({20.0, 0.0, -3.0}, {1, 0, 0}), true}).forceN.z, 1.0);
  EXPECT_EQ(s.totals().samplesRemoved, 0u);  // the tip, in free space, cut nothing
}

// The shaft meets level-0 voxels at 1.2 mm (refinement follows the cutting parts): their
// centres lie in rows 0.6 mm beside its axis, so its layer dips up to 0.8 mm below the faces.
TEST(ProxyCoupling, TheShaftNeverEntersBoneCoarse) {
  shaftPushedSideways(1.2, 2, 0.8);
}
TEST(ProxyCoupling, TheShaftNeverEntersBoneFine) {
  shaftPushedSideways(0.3, 0, 0.3);
}

// Turned about its tip, the drill's shaft swings down onto the slab: the proxy's turn stops
// there (its shaft holds no bone), and the rotational coupling's torque turns the command back
// toward it; the tip stays on the command.
TEST(ProxyCoupling, AShaftTurnedIntoBoneIsStoppedAndTwisted) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  const glm::dvec3 tip(20.0, 0.0, 3.0);  // beyond the slab's edge, the shaft over it
  HapticStep h;
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.001 * i;
    // Up to 15 degrees about y: the handle (toward -x) goes down.
    const double a = glm::radians(15.0) * std::min(1.0, t / 0.2);
    h = c.step({t, ToolPose::pointing(tip, {std::cos(a), 0.0, std::sin(a)}), false});
    expectSane(h);
    ASSERT_EQ(c.boneInsideInnerLayer(h.proxy, 1), 0.0) << t;
    ASSERT_EQ(h.proxy.tipMm, tip) << t;
    if (i == 0) {
      EXPECT_EQ(h.torqueNmm, glm::dvec3(0.0));
    }
  }
  // The proxy turned less than the command; the torque pulls the command's handle back up.
  const double proxyDeg = glm::degrees(std::asin(h.proxy.forward().z));
  std::printf("turned shaft: proxy %.2f deg of 15, torque %.2f N mm\n", proxyDeg,
              glm::length(h.torqueNmm));
  EXPECT_LT(proxyDeg, 14.0);
  EXPECT_GT(proxyDeg, 0.5);
  EXPECT_GT(glm::length(h.torqueNmm), 1.0);
  // The command's handle (toward -x) went down past the proxy's: the torque lifts it back.
  const glm::dvec3 handleCommand =
      -ToolPose::pointing(tip, {std::cos(glm::radians(15.0)), 0.0, std::sin(glm::radians(15.0))})
           .forward();
  const glm::dvec3 pushOnHandle =
      glm::cross(h.torqueNmm, handleCommand);  // where the torque moves it
  EXPECT_GT(pushOnHandle.z, 0.0);
}

TEST(ProxyCoupling, DrillingEatsItsWayInAndAllocatesNothing) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  double depth0 = 0.0;
  std::uint64_t allocations = 0;
  for (int i = 0; i <= 1500; ++i) {
    const double t = 0.001 * i;
    const double z = t < 0.1 ? 3.0 - 60.0 * t : -3.0;  // 6 mm past the surface, held
    const bool on = t >= 0.3;
    const std::uint64_t before = test::allocations();
    const HapticStep h = c.step({t, down({0.0, 0.0, z}), on});
    if (t >= 0.2) allocations += test::allocations() - before;
    expectSane(h);
    if (i == 300) depth0 = -c.proxy().tipMm.z;
  }
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(s.totals().samplesRemoved, 0u);
  // The proxy went in as the bone went, and stays out of what is left.
  EXPECT_GT(-c.proxy().tipMm.z, depth0 + 0.3);
  EXPECT_EQ(c.boneInsideInnerLayer(c.proxy(), 0, c.admittedRadiusMm(0)), 0.0);
  EXPECT_LT(c.admittedRadiusMm(0),
            s.simulation().tool().parts[0].innerRadiusMm);  // the drill cuts ahead
  EXPECT_EQ(c.boneInsideInnerLayer(c.proxy(), 1), 0.0);
}

// Every tool pushed 4 mm into bone with the drill off for 0.5 s (nothing removed, no part's
// layer holds bone), then on for 0.5 s (it cuts in, at most the feed limit's 5 mm/s): the drill
// and the burr down into the slab, the shaver sideways into a plate's edge with its window (its
// rounded ends, which do not cut, above and below the plate).
TEST(ProxyCoupling, EveryToolIsStoppedThenCutsItsWayIn) {
  for (const ToolKind kind : {ToolKind::Drill, ToolKind::Burr, ToolKind::Shaver}) {
    const bool shaver = kind == ToolKind::Shaver;
    SessionOptions o;
    o.voxelSizeMm = 1.2;
    o.levels = 2;
    o.tool = kind;
    o.keepSurface = false;
    const glm::dvec3 lo = shaver ? glm::dvec3(-8, -8, -2.4) : glm::dvec3(-8, -8, -8);
    Session s = Session::fromMesh(test::makeBox(lo, {8, 8, 0}), o, "slab");
    ProxyCoupling c(s.simulation());
    const Tool& tool = s.simulation().tool();
    const glm::dvec3 push = shaver ? glm::dvec3(-1.0, 0.0, 0.0) : glm::dvec3(0.0, 0.0, -1.0);
    const glm::dvec3 from = shaver ? glm::dvec3(8.0 + 3.0, 0.0, -3.2) : glm::dvec3(0.0, 0.0, 3.0);
    double atOffMm = 0.0;
    for (int i = 0; i <= 1000; ++i) {
      const double t = 0.001 * i;
      const glm::dvec3 tip = from + 7.0 * std::min(1.0, t / 0.1) * push;
      const HapticStep h = c.step({t, ToolPose::pointing(tip, {0.0, 0.0, -1.0}), t >= 0.5});
      expectSane(h);
      if (i == 499) {
        EXPECT_EQ(s.totals().samplesRemoved, 0u) << toolKindName(kind);
        for (int p = 0; p < tool.partCount; ++p)
          EXPECT_EQ(c.boneInsideInnerLayer(h.proxy, p), 0.0) << toolKindName(kind);
        atOffMm = glm::dot(h.proxy.tipMm, push);
      }
    }
    EXPECT_GT(s.totals().samplesRemoved, 0u) << toolKindName(kind);
    const double inMm = glm::dot(c.proxy().tipMm, push) - atOffMm;
    EXPECT_GT(inMm, 0.2) << toolKindName(kind);
    EXPECT_LE(inMm, 0.5 * 5.0 + 0.6) << toolKindName(kind);  // the feed limit, plus the cushion
    std::printf("%s: in %.3f mm in 0.5 s with the drill on\n", toolKindName(kind), inMm);
  }
}

TEST(ProxyCoupling, ABrokenCommandGivesNoForceAndKeepsTheProxy) {
  Session s = slabSession(1.2, 2);
  ProxyCoupling c(s.simulation());
  c.step({0.0, down({0.0, 0.0, 2.0}), false});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const HapticStep h = c.step({0.001, down({nan, 0.0, 1.0}), true});
  EXPECT_EQ(h.forceN, glm::dvec3(0.0));
  EXPECT_EQ(h.proxy.tipMm, glm::dvec3(0.0, 0.0, 2.0));
  const HapticStep after = c.step({0.002, down({0.0, 0.0, 1.9}), false});
  expectSane(after);
  EXPECT_EQ(after.proxy.tipMm, glm::dvec3(0.0, 0.0, 1.9));
}

TEST(ProxyCoupling, DirectStepIsTheSimulationsStep) {
  Session a = slabSession(1.2, 2), b = slabSession(1.2, 2);
  for (int i = 0; i < 300; ++i) {
    const StepInput in{0.001 * i, down({0.0, 0.0, 2.0 - 0.01 * i}), i > 100};
    const HapticStep h = stepHaptic(a.simulation(), nullptr, in);
    const StepOutput o = b.simulation().step(in);
    ASSERT_EQ(h.forceN, o.contact.forceN);
    ASSERT_EQ(h.proxy.tipMm, in.pose.tipMm);
  }
}

// The deterministic runner and the threaded runtime of a session under proxy coupling both
// step through it: the log's tip is the proxy's, its command the path's, the summary has the
// gap and the clamp count, and bone stops the tool in both.
TEST(ProxyCoupling, DeterministicAndThreadedRunsStepThroughTheSessionsCoupling) {
  SessionOptions o;
  o.voxelSizeMm = 1.2;
  o.levels = 2;
  o.keepSurface = false;
  o.coupling = CouplingMode::Proxy;
  // 8 mm into the slab in 0.2 s, held for 0.6 s, the drill off.
  const DrillPath path({{0.0, {0.0, 0.0, 3.0}, {1, 0, 0, 0}, false},
                        {0.2, {0.0, 0.0, -5.0}, {1, 0, 0, 0}, false},
                        {0.8, {0.0, 0.0, -5.0}, {1, 0, 0, 0}, false}});
  Session a = Session::fromMesh(test::makeBox({-8, -8, -8}, {8, 8, 0}), o, "slab");
  ASSERT_NE(a.coupling(), nullptr);
  const RunResult r = a.run(path);
  EXPECT_EQ(r.summary.coupling, CouplingMode::Proxy);
  EXPECT_GT(r.summary.maxGapMm, 5.0);
  EXPECT_GT(r.summary.clampSteps, 0u);
  EXPECT_EQ(r.summary.totals.samplesRemoved, 0u);
  EXPECT_GT(r.log.back().tipMm.z, 1.46 - 0.6);  // the tool on the surface
  EXPECT_DOUBLE_EQ(r.log.back().commandMm.z, -5.0);
  EXPECT_GT(r.log.back().forceN.z, 3.0);

  Session b = Session::fromMesh(test::makeBox({-8, -8, -8}, {8, 8, 0}), o, "slab");
  PathPoseSource source(path);
  RuntimeOptions ro;
  ro.durationS = 0.8;
  ro.realtimePriority = false;
  const RuntimeResult t = b.runThreaded(source, nullptr, ro);
  EXPECT_EQ(t.run.summary.coupling, CouplingMode::Proxy);
  EXPECT_GT(t.run.summary.maxGapMm, 5.0);
  EXPECT_EQ(t.run.summary.totals.samplesRemoved, 0u);
  ASSERT_FALSE(t.run.log.empty());
  EXPECT_GT(t.run.log.back().tipMm.z, 1.46 - 0.6);
  EXPECT_DOUBLE_EQ(t.run.log.back().commandMm.z, -5.0);
}

// ---- the built-in bone: a push with the drill off for 5 s, 10 mm past the surface, then on ----

}  // namespace
}  // namespace osteon::simulation
