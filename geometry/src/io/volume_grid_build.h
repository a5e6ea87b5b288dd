// Building a volume's VoxelGrid (volume_load.cpp): a brick at a time, and the inside distance
// the density rule of label maps and scalar volumes needs.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

// Chessboard distance (in voxels) from each inside voxel to the nearest outside voxel or the
// volume's edge, by two raster passes over the 26-neighbourhood; 0 outside. It is at most half
// the smallest edge (below 1626 for 2^32 voxels), so 16 bits hold it.
template <typename Inside>
std::vector<std::uint16_t> insideDistance(glm::ivec3 n, Inside inside) {
  std::vector<std::uint16_t> d(std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z));
  const auto idx = [&](int x, int y, int z) {
    return (std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x) + std::size_t(x);
  };
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = inside(i) ? 0xffff : 0;
  const auto pass = [&](int sign) {
    for (int zz = 0; zz < n.z; ++zz) {
      const int z = sign > 0 ? zz : n.z - 1 - zz;
      for (int yy = 0; yy < n.y; ++yy) {
        const int y = sign > 0 ? yy : n.y - 1 - yy;
        for (int xx = 0; xx < n.x; ++xx) {
          const int x = sign > 0 ? xx : n.x - 1 - xx;
          std::uint16_t& here = d[idx(x, y, z)];
          if (here == 0) continue;
          int best = here;
          for (int dz = -1; dz <= 0; ++dz) {
            for (int dy = -1; dy <= 1; ++dy) {
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const int nx = x + sign * dx, ny = y + sign * dy, nz = z + sign * dz;
                const int e = (nx < 0 || ny < 0 || nz < 0 || nx >= n.x || ny >= n.y || nz >= n.z)
                                  ? 0
                                  : d[idx(nx, ny, nz)];
                best = std::min(best, e + 1);
              }
            }
          }
          here = std::uint16_t(best);
        }
      }
    }
  };
  pass(1);
  pass(-1);
  return d;
}

// Sets every voxel from voxel(position, index, fill, density), a brick at a time: bricks whose
// voxels all agree stay unallocated (a volume's air and deep bone cost no voxel arrays).
// Returns the voxels inside (fill at or above half).
template <typename Voxel>
std::uint64_t buildGrid(VoxelGrid& grid, Voxel voxel) {
  const glm::ivec3 n = grid.dims(), nb = grid.brickDims();
  std::array<Fill, kBrickVoxels> fill{};
  std::array<Density, kBrickVoxels> density{};
  std::uint64_t inside = 0;
  for (int bz = 0; bz < nb.z; ++bz) {
    for (int by = 0; by < nb.y; ++by) {
      for (int bx = 0; bx < nb.x; ++bx) {
        const glm::ivec3 lo(bx * kBrickEdge, by * kBrickEdge, bz * kBrickEdge);
        const glm::ivec3 hi = glm::min(lo + kBrickEdge, n);
        if (hi - lo != glm::ivec3(kBrickEdge)) {  // a brick past the volume's edge: padding empty
          fill.fill(0);
          density.fill(0);
        }
        bool uniform = true;  // compared with the brick's first voxel, local 0
        for (int z = lo.z; z < hi.z; ++z) {
          for (int y = lo.y; y < hi.y; ++y) {
            std::size_t i =
                (std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x) +
                std::size_t(lo.x);
            for (int x = lo.x; x < hi.x; ++x, ++i) {
              const std::size_t local =
                  std::size_t(VoxelGrid::voxelInBrick({x - lo.x, y - lo.y, z - lo.z}));
              voxel(glm::ivec3(x, y, z), i, fill[local], density[local]);
              inside += fill[local] >= kFillHalf;
              uniform = uniform && fill[local] == fill[0] && density[local] == density[0];
            }
          }
        }
        const std::size_t brick = grid.brickIndex({bx, by, bz});
        if (uniform) {
          grid.setBrickUniform(brick, fill[0], density[0]);
          continue;
        }
        VoxelGrid::Brick& b = grid.materialiseBrick(brick);
        b.fill = fill;
        b.density = density;
      }
    }
  }
  grid.clearDirty();
  return inside;
}

}  // namespace osteon::geometry
