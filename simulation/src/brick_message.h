// Internal to osteon::simulation: a changed brick of the collision thread's grid, copied whole
// for the visual side's grid (live.cpp), so that neither reads a brick the other writes.
#pragma once

#include "osteon/geometry/voxels/voxel_grid.h"

#include <array>
#include <cstdint>

namespace osteon::simulation {

struct BrickMessage {
  std::uint32_t brick = 0;
  std::array<geometry::Fill, geometry::VoxelGrid::kBrickVoxels> fill{};
  std::array<geometry::Density, geometry::VoxelGrid::kBrickVoxels> density{};
};

// The brick as `grid` holds it now.
inline void snapshot(const geometry::VoxelGrid& grid, std::size_t brick, BrickMessage& msg) {
  msg.brick = std::uint32_t(brick);
  if (const geometry::VoxelGrid::Brick* data = grid.brickData(brick)) {
    msg.fill = data->fill;
    msg.density = data->density;
  } else {
    msg.fill.fill(grid.brickUniformFill(brick));
    msg.density.fill(grid.brickUniformDensity(brick));
  }
}

// Into `grid`, marked dirty for its surface.
inline void apply(geometry::VoxelGrid& grid, const BrickMessage& msg) {
  geometry::VoxelGrid::Brick& b = grid.materialiseBrick(msg.brick);
  b.fill = msg.fill;
  b.density = msg.density;
  grid.markBrickDirty(msg.brick);
}

}  // namespace osteon::simulation
