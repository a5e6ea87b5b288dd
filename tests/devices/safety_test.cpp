// The safety layer on synthetic streams: a non-finite pose at t = 2 s, a 20 ms gap, a 30 mm
// jump, a stalled haptic loop. The force sent never passes the limit, is never non-finite,
// and never changes by more than 0.1 N in one 1 ms step because of a fault; faulty poses never
// reach the session; every fault is counted once; forces come back through the ramp.
#include "osteon/devices/safety.h"

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "support/allocation_counter.h"

namespace osteon::devices {
namespace {

constexpr double kLimitN = 3.3;
constexpr double kTol = 1e-12;

// One step of a synthetic run, as the safety layer met it.
struct Step {
  double tS;
  glm::dvec3 sentN;
  ForceState state;
  std::uint32_t faults;
  PoseVerdict verdict;
};

// The force the simulation asks for at t: nothing at first, then up to 5 N (past the limit),
// turning slowly, as a drill pressed into bone would.
glm::dvec3 askedForce(double t) {
  if (t < 0.3) return glm::dvec3(0.0);
  const double magnitude = std::min(5.0, 6.0 * (t - 0.3));
  return magnitude * glm::dvec3(std::cos(0.4 * t), std::sin(0.4 * t), 0.5);
}

// The device's true motion: 10 mm/s along x.
glm::dvec3 truePose(double t) {
  return glm::dvec3(10.0 * t, 5.0, -3.0);
}

// Runs the layer over 5 s at 1 kHz with every fault kind:
//   t = 2.000      one non-finite sample
//   t = 3.000      a 20 ms gap (the device gives no new sample)
//   t = 3.500      one sample 30 mm off
//   t = 4.000      the haptic loop stalls: periods 3 ms apart for 30 ms
std::vector<Step> faultyRun(SafetyLayer& safety, std::uint64_t* allocationsInLoop = nullptr) {
  std::vector<Step> steps;
  steps.reserve(6000);
  DeviceSample sample;
  const std::uint64_t before = test::allocations();
  for (int ms = 0; ms <= 5000; ++ms) {
    const double t = ms * 0.001;
    if (ms > 4000 && ms < 4030 && ms % 3 != 0) continue;  // the loop does not run these periods
    safety.loopTick(t);
    const bool inGap = ms > 3000 && ms <= 3020;
    if (!inGap) {
      sample.tS = t;
      sample.positionMm = truePose(t);
      sample.orientation = glm::dquat(1.0, 0.0, 0.0, 0.0);
      sample.drillOn = true;
      if (ms == 2000) sample.positionMm.y = std::numeric_limits<double>::quiet_NaN();
      if (ms == 3500) sample.positionMm.z += 30.0;
    }
    const PoseVerdict& v = safety.acceptPose(t, sample);
    const glm::dvec3 sent = safety.limitForce(t, askedForce(t));
    steps.push_back({t, sent, safety.forceState(), v.faults, v});
  }
  if (allocationsInLoop) *allocationsInLoop = test::allocations() - before;
  return steps;
}

TEST(Safety, EveryFaultKindIsSurvivedCountedOnceAndNeverKicksTheHand) {
  SafetyLayer safety;
  const std::vector<Step> steps = faultyRun(safety);

  const FaultCounts& f = safety.stats().faults;
  EXPECT_EQ(f.nonFinite, 1u);
  EXPECT_EQ(f.gaps, 1u);
  EXPECT_EQ(f.jumps, 1u);
  EXPECT_EQ(f.watchdog, 1u);

  bool sawRampOut = false;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const Step& s = steps[i];
    ASSERT_TRUE(std::isfinite(s.sentN.x) && std::isfinite(s.sentN.y) && std::isfinite(s.sentN.z))
        << s.tS;
    ASSERT_LE(glm::length(s.sentN), kLimitN + kTol) << s.tS;
    if (i == 0) continue;
    const double change = glm::length(s.sentN - steps[i - 1].sentN);
    // A fault, or its ramp-out: never more than 0.1 N from one step to the next.
    if (s.faults != 0 || s.state == ForceState::RampOut ||
        steps[i - 1].state == ForceState::RampOut) {
      EXPECT_LE(change, 0.1 + kTol) << "t=" << s.tS;
      sawRampOut = sawRampOut || s.state == ForceState::RampOut;
    }
  }
  EXPECT_TRUE(sawRampOut);
  // About 35 ms from the cap to zero: the NaN at 2 s found the force at the limit.
  const auto at = [&](double t) {
    for (const Step& s : steps) {
      if (std::abs(s.tS - t) < 1e-9) return s;
    }
    ADD_FAILURE() << "no step at " << t;
    return steps.front();
  };
  EXPECT_NEAR(glm::length(at(1.999).sentN), kLimitN, 1e-9);
  EXPECT_NEAR(glm::length(at(2.010).sentN), kLimitN - 1.1, 1e-6);
  double zeroAt = -1.0;
  for (const Step& s : steps) {
    if (s.tS >= 2.0 && glm::length(s.sentN) == 0.0) {
      zeroAt = s.tS;
      break;
    }
  }
  EXPECT_NEAR(zeroAt, 2.033, 1e-9);  // 33 falls of 0.1 N from 3.3 N, the NaN step the first
  // Forces resume through the ramp after each fault, and are whole again before the end.
  EXPECT_EQ(at(5.0).state, ForceState::Engaged);
  EXPECT_NEAR(glm::length(at(5.0).sentN), kLimitN, 1e-9);
  EXPECT_GE(safety.stats().engagements, 4u);
  EXPECT_GT(safety.stats().clampedSteps, 1000u);  // 5 N asked for, 3.3 N sent
  EXPECT_GT(safety.stats().rampSteps, 500u);
}

TEST(Safety, FaultyPosesNeverReachTheSession) {
  SafetyLayer safety;
  const std::vector<Step> steps = faultyRun(safety);
  const PoseVerdict* previous = nullptr;
  double previousT = 0.0;
  for (const Step& s : steps) {
    const PoseVerdict& v = s.verdict;
    ASSERT_TRUE(v.valid);
    ASSERT_TRUE(std::isfinite(v.positionMm.x) && std::isfinite(v.positionMm.y) &&
                std::isfinite(v.positionMm.z))
        << s.tS;
    // Never the jumped pose: always where the device truly was at some moment.
    EXPECT_NEAR(v.positionMm.y, 5.0, 1e-12) << s.tS;
    EXPECT_NEAR(v.positionMm.z, -3.0, 1e-12) << s.tS;
    if (previous) {
      EXPECT_LE(glm::distance(v.positionMm, previous->positionMm),
                10.0 * std::max(1.0, (s.tS - previousT) / 0.001));
    }
    if (v.faults & (kFaultNonFinite | kFaultGap | kFaultJump)) {
      EXPECT_FALSE(v.drillOn) << s.tS;
    }
    previous = &v;
    previousT = s.tS;
  }
  // The held pose at the NaN and the jump is the one before.
  const auto verdictAt = [&](double t) {
    for (const Step& s : steps) {
      if (std::abs(s.tS - t) < 1e-9) return s;
    }
    return steps.front();
  };
  EXPECT_EQ(verdictAt(2.0).verdict.positionMm, truePose(1.999));
  EXPECT_TRUE(verdictAt(2.0).faults & kFaultNonFinite);
  EXPECT_EQ(verdictAt(3.5).verdict.positionMm, truePose(3.499));
  EXPECT_TRUE(verdictAt(3.5).faults & kFaultJump);
  EXPECT_TRUE(verdictAt(3.010).faults & kFaultGap);
  EXPECT_EQ(verdictAt(3.010).verdict.positionMm, truePose(3.0));
  // The loop ran at 4.000, 4.002, 4.005, 4.008: three missed periods in a row.
  EXPECT_FALSE(verdictAt(4.005).faults & kFaultWatchdog);
  EXPECT_TRUE(verdictAt(4.008).faults & kFaultWatchdog);
  EXPECT_EQ(verdictAt(4.011).verdict.positionMm,
            truePose(4.011));  // the watchdog holds forces, not poses
  EXPECT_EQ(verdictAt(4.5).faults, 0u);
  EXPECT_GT(safety.stats().heldSteps, 0u);
}

TEST(Safety, ThePerStepPathAllocatesNothing) {
  SafetyLayer safety;
  std::uint64_t allocations = 0;
  std::vector<Step> steps = faultyRun(safety, &allocations);
  // The only allocation in the loop is the test's own vector, reserved before it.
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(steps.size(), 5001u - 19u);  // the stalled loop skipped 19 periods
}

TEST(Safety, EngagesOnlyAfterAPoseAndASmallForceThenRampsInOverHalfASecond) {
  SafetyLayer safety;
  DeviceSample sample;
  // No pose yet: nothing is sent, however small the force.
  safety.loopTick(0.0);
  EXPECT_FALSE(safety.acceptPose(0.0, sample).valid);
  EXPECT_EQ(safety.limitForce(0.0, glm::dvec3(0.05, 0.0, 0.0)), glm::dvec3(0.0));
  EXPECT_EQ(safety.forceState(), ForceState::Off);
  // A pose, but the tool starts in the bone (1 N): still nothing.
  int engagedMs = -1;
  for (int ms = 1; ms <= 2000; ++ms) {
    const double t = ms * 0.001;
    sample.tS = t;
    sample.positionMm = glm::dvec3(0.0);
    safety.loopTick(t);
    safety.acceptPose(t, sample);
    const double asked = ms < 500 ? 1.0 : 0.1;  // pulled out at 0.5 s
    const glm::dvec3 sent = safety.limitForce(t, glm::dvec3(0.0, 0.0, asked));
    if (ms < 500) {
      EXPECT_EQ(sent, glm::dvec3(0.0)) << t;
    }
    if (engagedMs < 0 && safety.forceState() != ForceState::Off) engagedMs = ms;
    if (engagedMs > 0 && ms == engagedMs + 250) {
      EXPECT_NEAR(sent.z, 0.05, 1e-9);
    }  // half way up the ramp
    if (engagedMs > 0 && ms > engagedMs + 500) {
      EXPECT_NEAR(sent.z, 0.1, 1e-12);
    }
  }
  EXPECT_EQ(engagedMs, 500);
  EXPECT_EQ(safety.forceState(), ForceState::Engaged);
}

TEST(Safety, AStreamThatJumpedAndStaysIsFollowedOnceSettledAndASpikeIsDropped) {
  SafetyLayer safety;
  DeviceSample sample;
  int jumpedSteps = 0;
  for (int ms = 0; ms <= 300; ++ms) {
    const double t = ms * 0.001;
    sample.tS = t;
    // A spike at 50 ms; from 100 ms the device is 30 mm further on (moved while unobserved).
    sample.positionMm = glm::dvec3(ms >= 100 || ms == 50 ? 30.0 : 0.0, 0.0, 0.0);
    safety.loopTick(t);
    const PoseVerdict& v = safety.acceptPose(t, sample);
    if (ms == 50) {
      EXPECT_EQ(v.positionMm.x, 0.0);
    }
    if (ms == 51) {
      EXPECT_EQ(v.faults, 0u);
    }
    if (v.faults & kFaultJump) ++jumpedSteps;
    if (ms == 200) {
      EXPECT_EQ(v.positionMm.x, 30.0);
    }  // followed after resyncS (50 ms)
  }
  EXPECT_EQ(safety.stats().faults.jumps, 2u);
  EXPECT_EQ(jumpedSteps, 1 + 50);
}

TEST(Safety, GapsAndNonFiniteRunsCountOncePerEpisode) {
  SafetyLayer safety;
  DeviceSample sample;
  for (int ms = 0; ms <= 1000; ++ms) {
    const double t = ms * 0.001;
    const bool silent = (ms > 100 && ms < 200) || (ms > 600 && ms < 640);  // two gaps
    if (!silent) {
      sample.tS = t;
      sample.positionMm = glm::dvec3(0.0);
      if (ms >= 300 && ms < 320)
        sample.positionMm.x = std::numeric_limits<double>::infinity();     // one run
      if (ms == 400) sample.orientation = glm::dquat(0.0, 0.0, 0.0, 0.0);  // another
      if (ms == 401) sample.orientation = glm::dquat(1.0, 0.0, 0.0, 0.0);
    }
    safety.loopTick(t);
    safety.acceptPose(t, sample);
    safety.limitForce(t, glm::dvec3(std::numeric_limits<double>::quiet_NaN()));
  }
  EXPECT_EQ(safety.stats().faults.gaps, 2u);
  EXPECT_EQ(safety.stats().faults.nonFinite, 2u);
  EXPECT_EQ(safety.stats().faults.jumps, 0u);
  EXPECT_EQ(safety.stats().faults.watchdog, 0u);
  EXPECT_EQ(safety.stats().nonFiniteForces, 1001u);  // a non-finite force is never sent
  EXPECT_EQ(safety.stats().maxForceN, 0.0);
}

TEST(Safety, AReplayedRecordingStepsTheWatchdogAndGapsByItsRows) {
  // Rows 2 ms apart are a recording loop that missed its period: three in a row trip the
  // watchdog; one row after 20 ms of nothing is a gap, not a watchdog.
  SafetyLayer safety;
  const double rows[] = {0.000, 0.001, 0.002, 0.004, 0.006, 0.008, 0.009, 0.029, 0.030};
  for (double t : rows) safety.loopTick(t);
  EXPECT_EQ(safety.stats().faults.watchdog, 1u);
  DeviceSample sample;
  for (double t : rows) {
    sample.tS = t;
    safety.acceptPose(t, sample);
  }
  EXPECT_EQ(safety.stats().faults.gaps, 1u);
}

TEST(Safety, ClampsToTheDevicesLimit) {
  SafetyOptions options;
  options.forceLimitN = 1.0;
  options.rampInS = 0.001;
  SafetyLayer safety(options);
  DeviceSample sample;
  sample.tS = 0.0;
  safety.loopTick(0.0);
  safety.acceptPose(0.0, sample);
  safety.limitForce(0.0, glm::dvec3(0.0));  // engage
  sample.tS = 0.001;
  safety.loopTick(0.001);
  safety.acceptPose(0.001, sample);
  const glm::dvec3 sent = safety.limitForce(0.002, glm::dvec3(0.0, 3.0, 4.0));
  EXPECT_NEAR(glm::length(sent), 1.0, 1e-12);
  EXPECT_NEAR(sent.y / sent.z, 0.75, 1e-12);
  EXPECT_EQ(safety.stats().clampedSteps, 1u);
}

}  // namespace
}  // namespace osteon::devices
