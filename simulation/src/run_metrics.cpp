#include "osteon/simulation/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "osteon/core/assert.h"

namespace osteon::simulation {

Percentiles percentilesOf(std::vector<double> values) {
  Percentiles p;
  if (values.empty()) return p;
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) {
    return values[std::min(values.size() - 1, std::size_t(q * double(values.size())))];
  };
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.max = values.back();
  return p;
}

void Durations::add(std::int64_t ns) {
  OSTEON_ASSERT(ns >= 0, "a duration on a monotonic clock is never negative");
  maxNs_ = std::max(maxNs_, ns);
  ns_.push_back(
      std::uint32_t(std::clamp<std::int64_t>(ns, 0, std::numeric_limits<std::uint32_t>::max())));
}

void Durations::addMs(double ms) {
  add(std::int64_t(std::llround(ms * 1e6)));
}

Percentiles Durations::percentiles(double nsPerUnit) {
  Percentiles p;
  if (ns_.empty()) return p;
  std::sort(ns_.begin(), ns_.end());
  const auto at = [&](double q) {
    return double(ns_[std::min(ns_.size() - 1, std::size_t(q * double(ns_.size())))]) / nsPerUnit;
  };
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.max = double(maxNs_) / nsPerUnit;
  return p;
}

double forceJitterN(const std::vector<ForceLogRow>& log, double fromS, double toS, double windowS) {
  // Prefix sums of |F| make every centred window O(1).
  std::vector<double> prefix(log.size() + 1, 0.0);
  for (std::size_t i = 0; i < log.size(); ++i) prefix[i + 1] = prefix[i] + log[i].magnitudeN;
  double sum2 = 0.0;
  std::size_t count = 0, lo = 0, hi = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    const double t = log[i].tS;
    if (t < fromS || t > toS) continue;
    // A nanosecond of slack keeps the window symmetric (51 samples at 1 ms) despite rounding.
    while (lo < log.size() && log[lo].tS < t - 0.5 * windowS - 1e-9) ++lo;
    while (hi < log.size() && log[hi].tS <= t + 0.5 * windowS + 1e-9) ++hi;
    const double mean = (prefix[hi] - prefix[lo]) / double(hi - lo);
    const double e = log[i].magnitudeN - mean;
    sum2 += e * e;
    ++count;
  }
  return count > 0 ? std::sqrt(sum2 / double(count)) : 0.0;
}

double maxStepChangeN(const std::vector<ForceLogRow>& log) {
  double m = 0.0;
  for (std::size_t i = 1; i < log.size(); ++i)
    m = std::max(m, std::abs(log[i].magnitudeN - log[i - 1].magnitudeN));
  return m;
}

// The bounds are forceJitterN's window tests at t = fromS and t = toS, written the same way so
// that rounding keeps every row a window reaches.
ForceMetrics::ForceMetrics(double fromS, double toS, double windowS)
    : fromS_(fromS),
      toS_(toS),
      windowS_(windowS),
      keepFromS_(fromS - 0.5 * windowS - 1e-9),
      keepToS_(toS + 0.5 * windowS + 1e-9) {}

void ForceMetrics::reserveForStep(double stepS) {
  const double rows = (keepToS_ - keepFromS_) / stepS + 3.0;
  if (rows > 0.0 && rows < 1e7) kept_.reserve(std::size_t(rows));
}

void ForceMetrics::add(double tS, double magnitudeN) {
  OSTEON_ASSERT(kept_.empty() || kept_.back().tS <= tS, "rows come in time order");
  if (!(tS < keepFromS_) && tS <= keepToS_) {
    kept_.push_back({tS, magnitudeN, sum_});
    sumAfterKept_ = sum_ + magnitudeN;
  }
  sum_ += magnitudeN;
  if (any_) maxStepChangeN_ = std::max(maxStepChangeN_, std::abs(magnitudeN - lastN_));
  lastN_ = magnitudeN;
  any_ = true;
  maxForceN_ = std::max(maxForceN_, magnitudeN);
}

double ForceMetrics::jitterN() const {
  // forceJitterN's loop on the kept rows; the running sums are those of the whole log.
  const std::size_t n = kept_.size();
  const auto sumBefore = [&](std::size_t k) { return k < n ? kept_[k].sumBefore : sumAfterKept_; };
  double sum2 = 0.0;
  std::size_t count = 0, lo = 0, hi = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = kept_[i].tS;
    if (t < fromS_ || t > toS_) continue;
    while (lo < n && kept_[lo].tS < t - 0.5 * windowS_ - 1e-9) ++lo;
    while (hi < n && kept_[hi].tS <= t + 0.5 * windowS_ + 1e-9) ++hi;
    const double mean = (sumBefore(hi) - sumBefore(lo)) / double(hi - lo);
    const double e = kept_[i].magnitudeN - mean;
    sum2 += e * e;
    ++count;
  }
  return count > 0 ? std::sqrt(sum2 / double(count)) : 0.0;
}

}  // namespace osteon::simulation
