#include "surface_cells.h"

#include <algorithm>

namespace osteon::geometry::detail {

namespace {

// Uniform state of a grid brick: 0 outside, 1 inside, 2 mixed (allocated). Outside the grid
// everything is empty, so the surface closes at the border.
int brickState(const VoxelGrid& grid, const glm::ivec3& b) {
  const glm::ivec3 nb = grid.brickDims();
  if (b.x < 0 || b.y < 0 || b.z < 0 || b.x >= nb.x || b.y >= nb.y || b.z >= nb.z) return 0;
  const std::size_t i = grid.brickIndex(b);
  if (grid.brickAllocated(i)) return 2;
  return double(grid.brickUniformFill(i)) > kIso ? 1 : 0;
}

}  // namespace

bool cellBrickActive(const VoxelGrid& grid, const glm::ivec3& cb) {
  // A cell brick can hold surface when the bricks its cells read are not one uniform state.
  const int first = brickState(grid, cb);
  if (first == 2) return true;
  for (int d = 1; d < 8; ++d) {
    if (brickState(grid, cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1)) != first) return true;
  }
  return false;
}

void loadBlock(const VoxelGrid& grid, const glm::ivec3& cb, FillBlock& block) {
  // Straight from the up to eight grid bricks the block lies in (0 outside the grid).
  const glm::ivec3 nb = grid.brickDims();
  const glm::ivec3 dims = grid.dims();
  const glm::ivec3 base = cb * kCellBrick;
  for (int d = 0; d < 8; ++d) {
    const glm::ivec3 off(d & 1, (d >> 1) & 1, (d >> 2) & 1);
    const glm::ivec3 b = cb + off;
    // Block coordinates this brick supplies: 0..7 from the cell brick itself, 8 from the next.
    const glm::ivec3 from = off * kCellBrick;
    const glm::ivec3 to = from + (1 - off) * (kCellBrick - 1) + 1;
    const bool inGrid = b.x >= 0 && b.y >= 0 && b.z >= 0 && b.x < nb.x && b.y < nb.y && b.z < nb.z;
    const VoxelGrid::Brick* data = inGrid ? grid.brickData(grid.brickIndex(b)) : nullptr;
    const Fill uniform = inGrid ? grid.brickUniformFill(grid.brickIndex(b)) : Fill(0);
    for (int z = from.z; z < to.z; ++z)
      for (int y = from.y; y < to.y; ++y)
        for (int x = from.x; x < to.x; ++x) {
          const glm::ivec3 v = base + glm::ivec3(x, y, z);
          Fill f = 0;
          if (inGrid && v.x < dims.x && v.y < dims.y && v.z < dims.z) {
            f = data ? data->fill[std::size_t(VoxelGrid::voxelInBrick(v - b * kCellBrick))] : uniform;
          }
          block[std::size_t(x + kBlock * (y + kBlock * z))] = f;
        }
  }
}

void cellRange(const VoxelGrid& grid, const glm::ivec3& cb, glm::ivec3& lo, glm::ivec3& hi) {
  lo = glm::max(cb * kCellBrick, glm::ivec3(-1));
  hi = glm::min(cb * kCellBrick + kCellBrick, grid.dims());  // cells -1 .. dims-1
}

VertexInfo edgeVertexInfo(const VoxelGrid& grid, const glm::ivec3& voxel, int axis, Fill a, Fill b) {
  double t = (kIso - double(a)) / (double(b) - double(a));
  t = std::clamp(t, kEdgeMargin, 1.0 - kEdgeMargin);
  return {grid.voxelCentreMm(voxel), axis, t, 0, 0, voxel};
}

}  // namespace osteon::geometry::detail
