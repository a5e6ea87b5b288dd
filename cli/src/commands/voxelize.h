// `osteon voxelize MESH --voxel-size MM`: a mesh voxelized by Embree ray projection (seed 3.2),
// optionally written as NRRD.
#pragma once

#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct VoxelizeCommandOptions {
  simulation::BoneSource bone;  // a mesh or `default`, its units and voxel size
  bool robust = false;
  int raysPerAxis = 4;
  double corticalMm = 2.0;
  int corticalDensity = 40;
  int cancellousDensity = 15;
  std::string out;  // GRID.nrrd, empty for none
  bool json = false;
  bool allowEmpty = false;  // an empty grid exits 0 (still "empty": true), not 1
};

int runVoxelize(const VoxelizeCommandOptions& options);

}  // namespace osteon::cli
