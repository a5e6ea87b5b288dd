// Internal to osteon::simulation: what the threaded runtime's 1 kHz loops need of the
// platform (Linux): a monotonic clock, absolute sleeps, pinned and real-time threads, and
// memory that neither faults nor is given back while they run.
#pragma once

#include <cstdint>
#include <vector>

namespace osteon::simulation::realtime {

// CLOCK_MONOTONIC in ns.
std::int64_t nowNs();
// Sleeps until CLOCK_MONOTONIC reaches `deadline` (ns), through signals.
void sleepUntilNs(std::int64_t deadline);
// Writes the stack pages a loop may reach, so that none is first touched (a page fault)
// inside a period.
void prefaultStack();
// While the 1 kHz loops run, freed memory stays in the process (process-wide, once).
void keepFreedMemory();
// The CPUs this process may run on, in order.
std::vector<int> allowedCpus();
// Pins the calling thread to `cpu` (best effort; < 0: not pinned).
void pinTo(int cpu);
// SCHED_FIFO at `priority` for the calling thread; false without the privilege.
bool askRealtime(int priority);

}  // namespace osteon::simulation::realtime
