// A run's options and result. The deterministic mode (Session::run, for tests and
// experiments) steps haptic, collision-and-removal and visual work in one thread with a fixed
// 1 ms step, so the same input gives the same force log bit for bit; the threaded runtime
// (runtime.h, live.h) gives the same result. The force log is force_log.h's, the metrics
// run_metrics.h's.
#pragma once

#include "osteon/simulation/coupling.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/force_log.h"
#include "osteon/simulation/run_metrics.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

namespace osteon::simulation {

struct RunSummary {
  double jitterN = 0.0;           // design.md: RMS of |F| minus its 50 ms centred moving average, t in [2, 5] s
  double maxStepChangeN = 0.0;    // largest |F| change between consecutive samples
  double maxForceN = 0.0;
  double removedVolumeMm3 = 0.0;
  Percentiles hapticStepUs;       // collision + force + removal per step
  Percentiles remeshMs;           // incremental surface updates
  std::uint64_t overruns = 0;     // steps over their period (threaded runtime; 0 here)
  std::uint64_t steps = 0;
  DrillingTotals totals;  // the simulation's counters at the end of the run (drilling.h)
  CouplingMode coupling = CouplingMode::Direct;
  double maxGapMm = 0.0;          // largest proxy-to-commanded tip distance (0 under direct)
  std::uint64_t clampSteps = 0;   // steps whose force to the device was at N_max
  // Counts one haptic step in maxGapMm and clampSteps.
  void tally(const HapticStep& h) {
    maxGapMm = std::max(maxGapMm, h.gapMm);
    clampSteps += h.clamped ? 1 : 0;
  }
};

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
