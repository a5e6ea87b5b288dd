// Voxel grids that stress surface extraction, shared by geometry's surface tests (topology)
// and validation's exact checks of the same surfaces (CGAL).
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::test {

geometry::SurfaceOptions smoothing(int passes, bool taubin = false);
// The smoothing settings every watertightness check runs: none, the seed's 2 passes, many
// passes, and Taubin (whose negative steps push vertices the other way).
const std::vector<std::pair<std::string, geometry::SurfaceOptions>>& smoothingVariants();

geometry::VoxelGrid emptyGrid(glm::ivec3 dims, double voxelSizeMm = 1.0);
void setFull(geometry::VoxelGrid& g, const glm::ivec3& v);

// Fill values for the single-cube cases: plain full/empty (vertices at mid-edge), random on
// each side of the iso level, and the extremes next to it (kFillHalf - 1, kFillHalf) mixed with
// 0 and full, which drive vertices into the clamp margin at either end of their edge.
enum class CornerFills { Binary, Random, Extreme };

geometry::Fill cornerFill(bool inside, CornerFills mode, std::mt19937& rng);

// A 4^3 grid whose central 2x2x2 voxels are the corners of one cube, corner c at (1, 1, 1) +
// (c & 1, c >> 1 & 1, c >> 2 & 1) inside when bit c of `config` is set; the other voxels are
// `background` (empty, or full so the cube sits in a cavity's wall).
geometry::VoxelGrid singleCubeGrid(int config, geometry::Fill background, CornerFills mode,
                                   std::mt19937& rng);

// n^3 voxels of uniformly random fill (seeded per size and seed).
geometry::VoxelGrid noiseGrid(int n, std::uint32_t seed, double voxelSizeMm = 0.7);
// n^3 voxels of fills only at 0, just below and at the iso level, and full: vertices pile into
// the clamp margins at both ends of their edges, the hardest case for smoothing.
geometry::VoxelGrid extremeNoiseGrid(int n, std::uint32_t seed);

}  // namespace osteon::test
