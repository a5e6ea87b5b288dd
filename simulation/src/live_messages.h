// Internal to osteon::simulation: what the live runtime's threads hand each other (live.cpp):
// the device's pose, a changed brick of the collision thread's grid copied whole for the
// visual side's grid (so that neither reads a brick the other writes), and the display state.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/live.h"

namespace osteon::simulation::messages {

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

struct PoseMessage {
  double tS = -1.0;  // < 0: no pose yet
  ToolPose pose;
  bool drillOn = false;
  DrillSettings settings;
};

// The display state without the refined voxels (published every step).
struct DisplayCore {
  double tS = -1.0;
  ToolPose pose;
  ToolPose commanded;
  double gapMm = 0.0;
  bool drillOn = false;
  ContactForce contact;
  std::uint64_t removedFill = 0;
  double removedVolumeMm3 = 0.0;
  std::uint64_t steps = 0;
  DrillSettings settings;
};

struct RefinedList {
  int depth = 0;
  std::size_t count = 0;
  std::array<glm::ivec3, DisplayState::kMaxRefined> voxels;
};

}  // namespace osteon::simulation::messages
