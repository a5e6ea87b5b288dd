// The machine's own timing for osteon_bench_drilling: a fixed workload's noise, the CPU time
// the hypervisor steals, no-work 1 kHz loops (the floor any real-time loop here stands on).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <pthread.h>
#include <sched.h>
#include <string>
#include <thread>
#include <time.h>
#include <unistd.h>
#include <vector>

#include "osteon/simulation/runner.h"
#include "osteon/simulation/runtime.h"

namespace osteon::bench {

using simulation::Percentiles;
using simulation::percentilesOf;
using simulation::RuntimeStats;

// The machine's own timing noise: a fixed workload, the same every time (about a haptic step's
// median on the development machine, over a 256 KiB array), timed 7,001 times as the runner
// times a step. Its p99 over its p50 is what the machine adds to any step's p99.
inline Percentiles noiseFloor() {
  std::vector<double> data(32768, 1.0), us;
  us.reserve(7001);
  double sink = 0.0;
  for (int i = 0; i < 7001; ++i) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t j = 0; j < data.size(); j += 3) sink += std::sqrt(data[j] * double(j));
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
                     .count());
  }
  if (sink < 0.0) std::printf("unreachable\n");  // keeps the work
  return percentilesOf(us);
}

// CPU time the hypervisor gave to other guests while this one had work ("steal" in
// /proc/stat), in seconds since boot; -1 where the kernel does not say.
inline double stealSeconds() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  unsigned long long user, nice, system, idle, iowait, irq, softirq, steal;
  if (!(stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal) ||
      cpu != "cpu")
    return -1.0;
  return double(steal) / double(sysconf(_SC_CLK_TCK));
}

// The machine's own overrun floor: the runtime's two 1 kHz loops (SCHED_FIFO, absolute
// deadlines, the same overrun rule) with no work at all, beside a thread streaming through
// 64 MiB as a busy visual thread does. Every overrun here is the machine's.
struct OverrunFloor {
  std::uint64_t periods[2] = {0, 0}, overruns[2] = {0, 0};
  double stealS = 0.0;
};

using Clock = std::chrono::steady_clock;

// A no-work 1 kHz loop at SCHED_FIFO `priority` with the runtime's rule: absolute deadlines
// from `startAt`; a period whose wake-up ends after the period is an overrun (onOverrun gets
// its end), and the periods it missed are skipped. Runs while keepGoing(k); returns the periods.
template <class KeepGoing, class OnOverrun>
inline std::uint64_t noWorkLoop(int priority, Clock::time_point startAt, KeepGoing&& keepGoing,
                                OnOverrun&& onOverrun) {
  sched_param p{};
  p.sched_priority = priority;
  pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
  const auto period = std::chrono::milliseconds(1);
  std::uint64_t periods = 0;
  for (std::uint64_t k = 0; keepGoing(k);) {
    const auto deadline = startAt + k * period;
    std::this_thread::sleep_until(deadline);
    const auto end = Clock::now();
    ++periods;
    if (end > deadline + period) {
      onOverrun(end);
      k = std::uint64_t((end - startAt) / period) + 1;
    } else {
      ++k;
    }
  }
  return periods;
}

// A no-work 1 kHz loop (SCHED_FIFO, absolute deadlines, the runtime's overrun rule) running
// beside something else until stopped: the floor of that very window, with the same load,
// the same hypervisor steal and the same memory traffic as what it runs beside.
class ProbeLoop {
 public:
  ProbeLoop(int priority, std::chrono::microseconds offset) {
    overrunNs_.assign(RuntimeStats::kOverrunInstantsKept, 0);
    thread_ = std::thread([this, priority, offset] {
      periods_ = noWorkLoop(
          priority, Clock::now() + offset,
          [this](std::uint64_t) { return !stop_.load(std::memory_order_relaxed); },
          [this](Clock::time_point end) {
            if (overruns_ < overrunNs_.size())
              overrunNs_[overruns_] = end.time_since_epoch().count();
            ++overruns_;
          });
    });
  }
  void stop() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }
  ~ProbeLoop() { stop(); }
  std::uint64_t periods() const { return periods_; }
  std::uint64_t overruns() const { return overruns_; }
  // Steady-clock (CLOCK_MONOTONIC) ns of the first overruns, as RuntimeStats keeps them.
  std::vector<std::int64_t> overrunNs() const {
    return {overrunNs_.begin(), overrunNs_.begin() + std::ptrdiff_t(std::min<std::uint64_t>(
                                                         overruns_, overrunNs_.size()))};
  }

 private:
  std::vector<std::int64_t> overrunNs_;
  std::atomic<bool> stop_{false};
  std::uint64_t periods_ = 0, overruns_ = 0;
  std::thread thread_;
};

// Overruns of `a` that end within 2 ms of one of `b`'s: the same stall seen by both.
inline std::size_t coincident(const std::vector<std::int64_t>& a,
                              const std::vector<std::int64_t>& b) {
  std::size_t n = 0;
  for (const std::int64_t t : a) {
    for (const std::int64_t u : b) {
      if (std::llabs(t - u) <= 2000000) {
        ++n;
        break;
      }
    }
  }
  return n;
}

// `part` as a percentage of `whole` (0 when nothing ran).
inline double percentOf(std::uint64_t part, std::uint64_t whole) {
  return 100.0 * double(part) / double(std::max<std::uint64_t>(whole, 1));
}

inline OverrunFloor overrunFloor(double seconds) {
  OverrunFloor f;
  std::atomic<bool> stop{false};
  const auto startAt = Clock::now() + std::chrono::milliseconds(5);
  const auto periods = std::uint64_t(seconds * 1000.0);
  const auto loop = [&](int which, int priority, std::chrono::microseconds offset) {
    f.periods[which] = noWorkLoop(
        priority, startAt + offset, [&](std::uint64_t k) { return k < periods; },
        [&](Clock::time_point) { ++f.overruns[which]; });
  };
  const double steal0 = stealSeconds();
  std::thread busy([&] {
    std::vector<double> data(8 << 20, 1.0);
    double sink = 0.0;
    while (!stop.load(std::memory_order_relaxed)) {
      for (std::size_t i = 0; i < data.size(); i += 8) sink += data[i];
    }
    if (sink < 0.0) std::printf("unreachable\n");
  });
  std::thread haptic(loop, 0, 80, std::chrono::microseconds(0));
  std::thread collision(loop, 1, 79, std::chrono::microseconds(500));
  haptic.join();
  collision.join();
  stop.store(true);
  busy.join();
  f.stealS = stealSeconds() - steal0;
  return f;
}

// Where the machine's stalls land: one no-work 1 kHz loop pinned to each CPU (SCHED_FIFO 80,
// staggered), for `seconds`. Prints each CPU's overruns and how many of them fall within 2 ms
// of another CPU's: the case for the haptic loop's standby thread on a second CPU (runtime.h).
inline void cpuStalls(double seconds) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  sched_getaffinity(0, sizeof allowed, &allowed);
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(std::size_t(c), &allowed)) cpus.push_back(c);
  }
  std::vector<std::vector<std::int64_t>> at(cpus.size());
  const auto startAt = Clock::now() + std::chrono::milliseconds(5);
  const auto periods = std::uint64_t(seconds * 1000.0);
  std::vector<std::thread> loops;
  const double steal0 = stealSeconds();
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    loops.emplace_back([&, i] {
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(std::size_t(cpus[i]), &one);
      pthread_setaffinity_np(pthread_self(), sizeof one, &one);
      at[i].reserve(RuntimeStats::kOverrunInstantsKept);
      const auto offset =
          std::chrono::microseconds(1000 * std::int64_t(i) / std::int64_t(cpus.size()));
      noWorkLoop(
          80, startAt + offset, [&](std::uint64_t k) { return k < periods; },
          [&, i](Clock::time_point end) {
            if (at[i].size() < at[i].capacity()) at[i].push_back(end.time_since_epoch().count());
          });
    });
  }
  for (std::thread& t : loops) t.join();
  std::printf("no-work 1 kHz loops pinned one per CPU, %g s, stolen %.2f s:\n", seconds,
              stealSeconds() - steal0);
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    std::vector<std::int64_t> others;
    for (std::size_t j = 0; j < cpus.size(); ++j) {
      if (j != i) others.insert(others.end(), at[j].begin(), at[j].end());
    }
    std::printf("  CPU %d: %zu overran, %zu of them within 2 ms of another CPU's\n", cpus[i],
                at[i].size(), coincident(at[i], others));
  }
}

}  // namespace osteon::bench
