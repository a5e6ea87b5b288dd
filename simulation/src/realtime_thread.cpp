#include "realtime_thread.h"

#include <cerrno>
#include <malloc.h>
#include <mutex>
#include <pthread.h>
#include <sched.h>
#include <time.h>

namespace osteon::simulation::realtime {

std::int64_t nowNs() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return std::int64_t(t.tv_sec) * 1000000000 + t.tv_nsec;
}

void sleepUntilNs(std::int64_t deadline) {
  timespec t{};
  t.tv_sec = time_t(deadline / 1000000000);
  t.tv_nsec = long(deadline % 1000000000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
  }
}

// Writes the stack pages a loop may reach, so that none is first touched (a page fault)
// inside a period.
__attribute__((noinline)) void prefaultStack() {
  volatile std::uint8_t pages[128 * 1024];
  for (std::size_t i = 0; i < sizeof pages; i += 4096) pages[i] = 0;
}

// While the 1 kHz loops run, freed memory stays in the process: each munmap of a freed
// surface buffer (and each page fault of a fresh one) in the visual thread stalled the
// collision thread up to 4 ms and doubled the haptic thread's overruns at 0.3 mm
// (docs/performance.md, "Threaded runtime"). Process-wide and once: RSS stays at its peak.
void keepFreedMemory() {
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_MMAP_MAX, 0);         // large blocks from the heap too, not from fresh mappings
    mallopt(M_TRIM_THRESHOLD, -1);  // and the heap's top never given back
  });
}

// The CPUs this process may run on, in order.
std::vector<int> allowedCpus() {
  std::vector<int> cpus;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(std::size_t(c), &set)) cpus.push_back(c);
  }
  return cpus;
}

void pinTo(int cpu) {
  if (cpu < 0) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(std::size_t(cpu), &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);  // best effort: unpinned still runs
}

bool askRealtime(int priority) {
  sched_param p{};
  p.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0;
}

}  // namespace osteon::simulation::realtime
