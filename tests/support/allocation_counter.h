// Every heap allocation of a test program, counted, so a test can prove that a real-time loop
// (the safety layer, the drilling step, the proxy coupling) allocates nothing. Link
// support/allocation_counter.cpp into the program: it replaces the global operator new.
#pragma once

#include <cstdint>

namespace osteon::test {

// Allocations through operator new (and new[]) since the program started.
std::uint64_t allocations();
// Those made by the calling thread: allocations() minus this is every other thread's.
std::uint64_t threadAllocations();

}  // namespace osteon::test
