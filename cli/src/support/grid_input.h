// The grid hierarchy and mesh work on: a GRID.nrrd or other volume as read, or a mesh voxelized
// at --voxel-size, opened by BoneModel::open as it is, empty or not (the commands report an empty
// result), without a session's fine fills.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "osteon/core/timing.h"
#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct LoadedGrid {
  Clock::time_point start = Clock::now();  // the command's set-up starts here
  std::shared_ptr<const simulation::BoneModel> bone;
  double voxelizeMs = 0.0;         // the voxelizer's whole time, its density pass included
  nlohmann::json volume;           // what a volume was read as, null for a mesh
  std::string volumeText;          // its line of text ("" for a mesh or an osteon grid)
  simulation::SetupTimings setup;  // a volume's whole read, its density included, is its load
};

LoadedGrid loadGrid(simulation::BoneSource source);

}  // namespace osteon::cli
