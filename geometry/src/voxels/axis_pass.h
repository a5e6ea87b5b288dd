// One axis of the voxelizer's ray projection (voxelizer.cpp runs one per axis and combines
// them): the rays of each voxel column, their inside intervals' overlap with the voxels, and
// the fills stored brick by brick.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry::detail {

// One axis of ray projection: fills `out` (fill only) and marks columns where no ray could
// be classified (robust mode abstains there).
struct AxisPass {
  const EmbreeScene* scene;
  const VoxelGrid* layout;
  int axis;
  int raysPerAxis;
  bool abstain;     // robust: unresolved rays do not vote
  int outwardSign;  // +1 outward mesh, -1 inward, 0 when orientation is unknown
  VoxelGrid* out;
  std::vector<std::uint8_t>* columnKnown;  // (u, v) bitmap, u fastest
  std::atomic<std::uint64_t> raysCast{0}, raysRetried{0}, raysUnresolved{0}, raysWinding{0};
  std::atomic<std::uint64_t> abstainedColumns{0};
};

// Runs the pass over every column of bricks across its axis, in parallel.
void runAxisPass(AxisPass& pass);

}  // namespace osteon::geometry::detail
