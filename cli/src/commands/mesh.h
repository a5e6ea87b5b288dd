// `osteon mesh MESH|GRID`: the crack-free (or the seed's naive) surface of a voxelized mesh or a
// grid, its topology, optionally written as a mesh file.
#pragma once

#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct MeshCommandOptions {
  simulation::BoneSource bone;  // a mesh, `default`, a GRID.nrrd or another volume
  std::string method = "crackfree";
  int smooth = 2;
  bool taubin = false;
  std::string out;
  bool json = false;
  bool allowEmpty = false;
};

int runMesh(const MeshCommandOptions& options);

}  // namespace osteon::cli
