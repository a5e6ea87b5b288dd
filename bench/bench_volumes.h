// The volumes surface extraction is measured on, shared by the benchmark (surface_bench.cpp)
// and the per-process comparison (extract_peer.cpp, extract_interleaved.sh).
#pragma once

#include <string>

#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::bench {

// The built-in humerus, built once.
const geometry::HumerusModel& humerusModel();
// An n^3 volume, built once per process: "humerus" (the built-in humerus in the middle), or
// any other name, a sphere filling it with three drilled tunnels.
const geometry::VoxelGrid& benchVolume(const std::string& name, int n);

}  // namespace osteon::bench
