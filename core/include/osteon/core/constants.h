// Constants more than one module is built around.
#pragma once

namespace osteon {

// Voxel grids are stored in cubic bricks of kBrickEdge^3 voxels (x fastest, then y, then z);
// surface extraction walks cells in bricks of the same edge.
inline constexpr int kBrickLog2 = 3;
inline constexpr int kBrickEdge = 1 << kBrickLog2;
inline constexpr int kBrickVoxels = kBrickEdge * kBrickEdge * kBrickEdge;

}  // namespace osteon
