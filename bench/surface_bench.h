// What the surface benches share (surface_bench.cpp: extraction; surface_tables_bench.cpp: the
// incremental update and the seed's Tables 1 and 2).
#pragma once

#include <chrono>

#include "osteon/geometry/io/humerus_model.h"

namespace osteon::bench {

using Clock = std::chrono::steady_clock;
// The built-in humerus, built once.
const geometry::HumerusModel& humerusModel();
// Registers the seed's tables' benchmarks (they need the shared data's path at run time).
void registerTables();

}  // namespace osteon::bench
