// What the surface benches share (surface_bench.cpp: extraction; surface_tables_bench.cpp: the
// incremental update and the seed's Tables 1 and 2).
#pragma once

#include <chrono>

#include "bench_volumes.h"

namespace osteon::bench {

using Clock = std::chrono::steady_clock;
// Registers the seed's tables' benchmarks (they need the shared data's path at run time).
void registerTables();

}  // namespace osteon::bench
