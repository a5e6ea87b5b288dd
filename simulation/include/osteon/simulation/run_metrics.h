// The metrics of a run (defined in docs/validation.md, "Force metrics"): step-time percentiles
// kept in little memory, the force jitter and the largest step change, over a whole log or row by
// row as a run goes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "osteon/simulation/force_log.h"

namespace osteon::simulation {

struct Percentiles {
  double p50 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
};
Percentiles percentilesOf(std::vector<double> values);

// Durations in whole nanoseconds, 4 bytes each: exact percentiles of a long run in little
// memory. add() allocates only past the reserved capacity.
class Durations {
 public:
  // Room for n durations, its pages written now: a first write to a fresh page in a 1 kHz
  // loop is a page fault, which waits whenever another thread holds the address space's lock
  // (an munmap of a freed surface buffer), often past the period.
  void reserve(std::size_t n) {
    ns_.assign(n, 0u);
    ns_.clear();
  }
  bool full() const { return ns_.size() >= ns_.capacity(); }
  void add(std::int64_t ns);
  // A duration chrono gave in milliseconds from whole nanoseconds: kept exactly.
  void addMs(double ms);
  // As percentilesOf() on ns / nsPerUnit (1e3: microseconds, 1e6: milliseconds). Sorts.
  Percentiles percentiles(double nsPerUnit);

 private:
  std::vector<std::uint32_t> ns_;  // saturated at 4.29 s; the max is kept apart
  std::int64_t maxNs_ = 0;
};

// Jitter as docs/validation.md defines it; 0 when no sample lies in [fromS, toS].
double forceJitterN(const std::vector<ForceLogRow>& log, double fromS = 2.0, double toS = 5.0,
                    double windowS = 0.05);
double maxStepChangeN(const std::vector<ForceLogRow>& log);

// The summary's force metrics from rows given one at a time in time order, bit for bit those
// of forceJitterN, maxStepChangeN and the largest |F| on the whole log, keeping only the rows
// the jitter's windows reach (t in [fromS - windowS / 2, toS + windowS / 2]).
class ForceMetrics {
 public:
  explicit ForceMetrics(double fromS = 2.0, double toS = 5.0, double windowS = 0.05);
  // Room for the kept rows at this step, so that add() does not allocate.
  void reserveForStep(double stepS);
  void add(double tS, double magnitudeN);
  double jitterN() const;
  double maxStepChangeN() const { return maxStepChangeN_; }
  double maxForceN() const { return maxForceN_; }

 private:
  struct Kept {
    double tS, magnitudeN, sumBefore;  // sumBefore: of |F| over every earlier row
  };
  double fromS_, toS_, windowS_, keepFromS_, keepToS_;
  std::vector<Kept> kept_;
  double sum_ = 0.0;           // of |F| over every row so far
  double sumAfterKept_ = 0.0;  // ... up to and including the last kept row
  double lastN_ = 0.0;
  bool any_ = false;
  double maxStepChangeN_ = 0.0, maxForceN_ = 0.0;
};

}  // namespace osteon::simulation
