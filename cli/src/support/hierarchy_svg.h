// A z-slice of a Dynamic Proximity Hierarchy as an SVG drawing, in the colours of the seed's
// Fig. 4 (level 0 red, 1 yellow, 2 green, 3 blue, 4 purple).
#pragma once

#include <string>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::cli {

// Level-0 voxels of slice `sliceZ` filled by their fill fraction; for every level above, the
// cells of alive nodes that cross the slice, outlined. Throws InputError if path can't be written.
void writeHierarchySvg(const geometry::DynamicProximityHierarchy& hierarchy,
                       const geometry::VoxelGrid& grid, int sliceZ, const std::string& title,
                       const std::string& path);

}  // namespace osteon::cli
