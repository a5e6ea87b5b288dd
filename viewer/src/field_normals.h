// Shading normals from the fill field's gradient: the marching-cubes normals of a surface
// extracted at 1.2 mm (or 0.54 mm) voxels follow its triangles and show terraces and contour
// rings; the gradient of the voxels' fill (Sobel at the voxel centres, blended trilinearly to the
// vertex) turns smoothly across them. Only the normals change: the mesh's
// positions and triangles (and so every crack-free guarantee) stay as extracted.
#pragma once

#include <glm/vec3.hpp>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::viewer {

// Where the field's normal disagrees with the mesh's by more than this (a feature finer than
// the gradient's reach, such as a drilled hole a few voxels across), the mesh's is kept.
inline constexpr double kFieldNormalMinCos = 0.5;

// The unit outward normal of `grid`'s fill at pMm (minus its gradient), or `meshNormal` where
// the gradient vanishes or disagrees with it (kFieldNormalMinCos). No allocation.
glm::dvec3 fieldNormal(const geometry::VoxelGrid& grid, const glm::dvec3& pMm,
                       const glm::dvec3& meshNormal);

}  // namespace osteon::viewer
