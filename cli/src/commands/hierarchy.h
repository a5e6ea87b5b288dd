// `osteon hierarchy MESH|GRID`: the Dynamic Proximity Hierarchy (seed 3.3) over a voxelized mesh
// or a grid, its invariants checked, optionally a z-slice of it drawn as SVG.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

struct HierarchyOptions {
  simulation::BoneSource bone;  // a mesh, `default`, a GRID.nrrd or another volume
  int xi = 3;
  std::uint64_t seed = 1;
  std::string svg;  // a slice of the hierarchy as SVG, empty for none
  std::optional<double> sliceZMm;
  bool json = false;
  bool allowEmpty = false;
};

int runHierarchy(const HierarchyOptions& options);

}  // namespace osteon::cli
