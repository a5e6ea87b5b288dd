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
  // Straight from the up to eight grid bricks the block lies in, a row at a time (0 outside
  // the grid).
  const glm::ivec3 nb = grid.brickDims();
  const glm::ivec3 dims = grid.dims();
  const glm::ivec3 base = cb * kCellBrick;
  block.fill(0);
  for (int d = 0; d < 8; ++d) {
    const glm::ivec3 off(d & 1, (d >> 1) & 1, (d >> 2) & 1);
    const glm::ivec3 b = cb + off;
    if (b.x < 0 || b.y < 0 || b.z < 0 || b.x >= nb.x || b.y >= nb.y || b.z >= nb.z) continue;
    // Block coordinates this brick supplies: 0..7 from the cell brick itself, 8 from the next,
    // clipped to the grid.
    const glm::ivec3 from = off * kCellBrick;
    const glm::ivec3 to = glm::min(from + (1 - off) * (kCellBrick - 1) + 1, dims - base);
    if (to.x <= from.x || to.y <= from.y || to.z <= from.z) continue;
    const std::size_t brick = grid.brickIndex(b);
    const VoxelGrid::Brick* data = grid.brickData(brick);
    const Fill uniform = grid.brickUniformFill(brick);
    const int count = to.x - from.x;
    for (int z = from.z; z < to.z; ++z)
      for (int y = from.y; y < to.y; ++y) {
        Fill* dst = block.data() + (from.x + kBlock * (y + kBlock * z));
        if (data) {
          const glm::ivec3 local = base + glm::ivec3(from.x, y, z) - b * kCellBrick;
          std::copy_n(data->fill.data() + VoxelGrid::voxelInBrick(local), count, dst);
        } else if (uniform != 0) {
          std::fill_n(dst, count, uniform);
        }
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
