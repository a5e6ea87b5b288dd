// The table of degradation counters: each entry reads its own field of a run's summary, the
// keys are distinct, and a summary is degraded exactly when one of them is non-zero.
#include <iterator>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "osteon/simulation/runner.h"

namespace osteon::simulation {
namespace {

// Each counter set to its own value (its index + 1), through the fields the summary has.
RunSummary numbered() {
  RunSummary s;
  s.clampSteps = 1;
  s.totals.stepsDeferred = 2;
  s.totals.voxelsDeferred = 3;
  s.totals.refinePoolExhausted = 4;
  s.totals.brickAllocations = 5;
  s.totals.cutOverflows = 6;
  s.totals.maskOverflows = 7;
  s.totals.nonFiniteForces = 8;
  s.overruns = 9;
  s.ringFull = 10;
  s.logDropped = 11;
  return s;
}

TEST(Degradation, EachCounterReadsItsOwnFieldUnderItsOwnKey) {
  const RunSummary s = numbered();
  std::set<std::string> keys;
  for (std::size_t i = 0; i < kDegradationCounters.size(); ++i) {
    const DegradationCounter& c = kDegradationCounters[i];
    SCOPED_TRACE(c.key);
    EXPECT_EQ(c.count(s), i + 1);
    EXPECT_TRUE(keys.insert(c.key).second);
    EXPECT_GT(std::string(c.meaning).size(), 10u);
    EXPECT_EQ(c.runtimeOnly,
              std::string(c.key) == "ring_full" || std::string(c.key) == "log_dropped");
  }
}

// The fields set one at a time, written here apart from the table.
using Setter = void (*)(RunSummary&);
const std::pair<const char*, Setter> kFields[] = {
    {"clamp_steps", [](RunSummary& s) { s.clampSteps = 1; }},
    {"refine_steps_deferred", [](RunSummary& s) { s.totals.stepsDeferred = 1; }},
    {"refine_voxels_deferred", [](RunSummary& s) { s.totals.voxelsDeferred = 1; }},
    {"refine_pool_exhausted", [](RunSummary& s) { s.totals.refinePoolExhausted = 1; }},
    {"brick_allocations", [](RunSummary& s) { s.totals.brickAllocations = 1; }},
    {"cut_overflows", [](RunSummary& s) { s.totals.cutOverflows = 1; }},
    {"mask_overflows", [](RunSummary& s) { s.totals.maskOverflows = 1; }},
    {"non_finite_forces", [](RunSummary& s) { s.totals.nonFiniteForces = 1; }},
    {"overruns", [](RunSummary& s) { s.overruns = 1; }},
    {"ring_full", [](RunSummary& s) { s.ringFull = 1; }},
    {"log_dropped", [](RunSummary& s) { s.logDropped = 1; }},
};

TEST(Degradation, ASummaryIsDegradedExactlyWhenACounterIsNotZero) {
  RunSummary clean;
  clean.steps = 7001;
  clean.maxForceN = 2.0;
  clean.maxGapMm = 0.5;
  clean.totals.removedFill = 1000;  // drilling counters that are no degradation
  clean.totals.queryWalks = 50;
  EXPECT_FALSE(degraded(clean));
  ASSERT_EQ(std::size(kFields), kDegradationCounters.size());
  for (const auto& [key, set] : kFields) {
    SCOPED_TRACE(key);
    RunSummary one = clean;
    set(one);
    EXPECT_TRUE(degraded(one));
    for (const DegradationCounter& c : kDegradationCounters) {
      EXPECT_EQ(c.count(one), std::string(c.key) == key ? 1u : 0u) << c.key;
    }
  }
}

}  // namespace
}  // namespace osteon::simulation
