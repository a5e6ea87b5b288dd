// A run's options and result. The deterministic mode (Session::run, for tests and
// experiments) steps haptic, collision-and-removal and visual work in one thread with a fixed
// 1 ms step, so the same input gives the same force log bit for bit; the threaded runtime
// (runtime.h, live.h) gives the same result. The force log is force_log.h's, the metrics
// run_metrics.h's.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "osteon/simulation/coupling.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/force_log.h"
#include "osteon/simulation/run_metrics.h"

namespace osteon::simulation {

struct RunSummary {
  double jitterN = 0.0;         // docs/validation.md, "Force metrics" (t in [2, 5] s)
  double maxStepChangeN = 0.0;  // largest |F| change between consecutive samples
  double maxForceN = 0.0;
  double removedVolumeMm3 = 0.0;
  Percentiles hapticStepUs;    // collision + force + removal per step
  Percentiles remeshMs;        // incremental surface updates
  std::uint64_t overruns = 0;  // steps over their period (threaded runtime; 0 here)
  std::uint64_t steps = 0;
  DrillingTotals totals;  // the simulation's counters at the end of the run (drilling.h)
  CouplingMode coupling = CouplingMode::Direct;
  double maxGapMm = 0.0;         // largest proxy-to-commanded tip distance (0 under direct)
  std::uint64_t clampSteps = 0;  // steps whose force to the device was at N_max
  // The threaded runtime's hand-offs (RuntimeStats; 0 in the deterministic mode).
  std::uint64_t ringFull = 0;    // changed bricks the visual side had to wait for
  std::uint64_t logDropped = 0;  // force log rows lost on the way to the logging thread
  // Counts one haptic step in maxGapMm and clampSteps.
  void tally(const HapticStep& h) {
    maxGapMm = std::max(maxGapMm, h.gapMm);
    clampSteps += h.clamped ? 1 : 0;
  }
};

// Every counter by which a run says it fell back on less than its design (a coarser or clamped
// force, a zeroed one, a late period, a brick or row that had to wait or was lost), in one
// table: summary.json reports each under its key (the threaded runtime's own in its "runtime"
// object) and "degraded" is true when any is non-zero.
struct DegradationCounter {
  const char* key;  // the summary.json field
  const char* meaning;
  bool runtimeOnly;  // reported in the threaded runtime's "runtime" object
  std::uint64_t (*count)(const RunSummary& summary);
};

inline constexpr std::array<DegradationCounter, 11> kDegradationCounters{{
    {"clamp_steps", "steps whose force to the device was at N_max", false,
     [](const RunSummary& s) { return s.clampSteps; }},
    {"refine_steps_deferred", "steps that left shell voxels coarse (the refinement budget)", false,
     [](const RunSummary& s) { return s.totals.stepsDeferred; }},
    {"refine_voxels_deferred", "shell voxels left coarse, summed over the steps", false,
     [](const RunSummary& s) { return s.totals.voxelsDeferred; }},
    {"refine_pool_exhausted", "voxels left coarse because the refinement pool was full", false,
     [](const RunSummary& s) { return s.totals.refinePoolExhausted; }},
    {"brick_allocations", "bricks a step allocated (the spare pool ran out)", false,
     [](const RunSummary& s) { return s.totals.brickAllocations; }},
    {"cut_overflows", "cuts that found more voxels than reserved (the rest left)", false,
     [](const RunSummary& s) { return s.totals.cutOverflows; }},
    {"mask_overflows", "removal masks the table had no room for", false,
     [](const RunSummary& s) { return s.totals.maskOverflows; }},
    {"non_finite_forces", "steps whose force was not finite (zero sent)", false,
     [](const RunSummary& s) { return s.totals.nonFiniteForces; }},
    {"overruns", "periods whose work ended past their deadline (threaded)", false,
     [](const RunSummary& s) { return s.overruns; }},
    {"ring_full", "changed bricks the visual side had to wait for (threaded)", true,
     [](const RunSummary& s) { return s.ringFull; }},
    {"log_dropped", "force log rows lost on the way to the logging thread (threaded)", true,
     [](const RunSummary& s) { return s.logDropped; }},
}};

// True when any counter of kDegradationCounters is non-zero.
inline bool degraded(const RunSummary& summary) {
  for (const DegradationCounter& c : kDegradationCounters) {
    if (c.count(summary) > 0) return true;
  }
  return false;
}

struct DeterministicOptions {
  double stepS = 0.001;
  int remeshEverySteps = 1;  // the visual work: incremental surface update every N steps (0: none)
  // Called after each step (and its surface update), for checks that follow a run.
  std::function<void(std::size_t step, const StepInput& input, const StepOutput& output)> afterStep;
  // Rows as they come (e.g. ForceLogWriter::write); must not throw.
  std::function<void(const ForceLogRow& row)> onRow;
  // The proxy coupling the run steps through (coupling.h); null: direct, the path's pose is
  // the tool's. afterStep then sees the proxy's pose.
  ProxyCoupling* coupling = nullptr;
  // Also collects every row in RunResult::log: for short paths (tests, experiments); the CLI
  // streams through onRow instead, so memory does not grow with the path.
  bool keepLog = true;
};

struct RunResult {
  std::vector<ForceLogRow> log;
  RunSummary summary;
};

}  // namespace osteon::simulation
