#include <utility>

#include "run_recorder.h"

namespace osteon::simulation {

RunRecorder::RunRecorder(std::function<void(const ForceLogRow&)> onRow, bool keepLog, double stepS)
    : onRow_(std::move(onRow)), keepLog_(keepLog) {
  metrics_.reserveForStep(stepS);
}

void RunRecorder::reserve(std::size_t rows) {
  if (keepLog_) log_.reserve(rows);
}

RunResult RunRecorder::finish(const DrillingSimulation& sim, bool proxy) {
  RunResult result;
  result.log = std::move(log_);
  RunSummary& s = result.summary;
  s.jitterN = metrics_.jitterN();
  s.maxStepChangeN = metrics_.maxStepChangeN();
  s.maxForceN = metrics_.maxForceN();
  s.removedVolumeMm3 = sim.removedVolumeMm3();
  s.totals = sim.totals();
  s.coupling = proxy ? CouplingMode::Proxy : CouplingMode::Direct;
  return result;
}

}  // namespace osteon::simulation
