#include "field_normals.h"

#include <cmath>

namespace osteon::viewer {

namespace {

// The fill of the 4 x 4 x 4 voxels from `first`, outside the grid empty.
void gatherBlock(const geometry::VoxelGrid& grid, const glm::ivec3& first, double (&f)[4][4][4]) {
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        const glm::ivec3 v = first + glm::ivec3(x, y, z);
        f[z][y][x] = grid.inBounds(v) ? double(grid.fill(v)) : 0.0;
      }
}

// The Sobel gradient at block voxel (x, y, z), 1..2 each: central differences smoothed 1-2-1
// across, so the fill's quantization and the voxelizer's sampling do not ripple the normal.
glm::dvec3 sobel(const double (&f)[4][4][4], int x, int y, int z) {
  static constexpr double w[3] = {1.0, 2.0, 1.0};
  glm::dvec3 g(0.0);
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b) {
      const double k = w[a + 1] * w[b + 1];
      g.x += k * (f[z + b][y + a][x + 1] - f[z + b][y + a][x - 1]);
      g.y += k * (f[z + b][y + 1][x + a] - f[z + b][y - 1][x + a]);
      g.z += k * (f[z + 1][y + b][x + a] - f[z - 1][y + b][x + a]);
    }
  return g;
}

}  // namespace

glm::dvec3 fieldNormal(const geometry::VoxelGrid& grid, const glm::dvec3& pMm,
                       const glm::dvec3& meshNormal) {
  // Voxel centres are the lattice: the cell whose 8 centres surround pMm, and where in it.
  const glm::dvec3 g = grid.gridFromWorld(pMm) - 0.5;
  if (!(std::isfinite(g.x) && std::isfinite(g.y) && std::isfinite(g.z))) return meshNormal;
  const glm::dvec3 base = glm::floor(g);
  const glm::dvec3 t = g - base;
  double f[4][4][4];
  gatherBlock(grid, glm::ivec3(base) - 1, f);
  glm::dvec3 gradient(0.0);
  for (int corner = 0; corner < 8; ++corner) {
    const glm::ivec3 o(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    const double w = (o.x ? t.x : 1.0 - t.x) * (o.y ? t.y : 1.0 - t.y) * (o.z ? t.z : 1.0 - t.z);
    if (w > 0.0) gradient += w * sobel(f, 1 + o.x, 1 + o.y, 1 + o.z);
  }
  const double length = glm::length(gradient);
  if (!(length > 1e-9)) return meshNormal;
  const glm::dvec3 n = -gradient / length;  // fill grows inwards
  const double meshLength = glm::length(meshNormal);
  if (meshLength > 1e-12 && glm::dot(n, meshNormal) < kFieldNormalMinCos * meshLength)
    return meshNormal;
  return n;
}

}  // namespace osteon::viewer
