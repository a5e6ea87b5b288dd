// Wall-clock timing for reports (not for the real-time loop's deadlines).
#pragma once

#include <chrono>

namespace osteon {

using Clock = std::chrono::steady_clock;

// Milliseconds from `start` to now.
inline double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace osteon
