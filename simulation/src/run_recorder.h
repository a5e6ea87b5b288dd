// Internal to osteon::simulation: the rows of a run into its result, written once for the
// deterministic mode (Session::run) and the threaded runtime's logging thread (live.cpp).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "osteon/simulation/runner.h"

namespace osteon::simulation {

class RunRecorder {
 public:
  RunRecorder(std::function<void(const ForceLogRow&)> onRow, bool keepLog, double stepS);
  // Room for `rows` rows: add() allocates nothing for them.
  void reserve(std::size_t rows);
  // One row, in time order: the summary's force metrics, the caller's onRow, the kept log.
  void add(const ForceLogRow& row) {
    metrics_.add(row.tS, row.magnitudeN);
    if (onRow_) onRow_(row);
    if (keepLog_) log_.push_back(row);
  }
  // The kept log and a summary with the force metrics, the simulation's removed volume and
  // totals, and the coupling mode; the caller adds timings and counts.
  RunResult finish(const DrillingSimulation& sim, bool proxy);

 private:
  std::function<void(const ForceLogRow&)> onRow_;
  bool keepLog_;
  ForceMetrics metrics_;
  std::vector<ForceLogRow> log_;
};

}  // namespace osteon::simulation
