// Building a volume's VoxelGrid (volume_load.cpp): a brick at a time, and the inside distance
// the density rule of label maps and scalar volumes needs.
#pragma once

#include <algorithm>
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

// Sets every voxel from voxel(position, index, fill, density), a row of bricks at a time with
// the voxels visited in storage order (x fastest: the values are read as they lie in memory),
// then each brick stored: bricks whose voxels all agree stay unallocated (a volume's air and deep
// bone cost no voxel arrays). Returns the voxels inside (fill at or above half).
template <typename Voxel>
std::uint64_t buildGrid(VoxelGrid& grid, Voxel voxel) {
  const glm::ivec3 n = grid.dims(), nb = grid.brickDims();
  std::vector<std::array<Fill, kBrickVoxels>> fill(std::size_t(nb.x));
  std::vector<std::array<Density, kBrickVoxels>> density(std::size_t(nb.x));
  std::uint64_t inside = 0;
  for (int bz = 0; bz < nb.z; ++bz) {
    for (int by = 0; by < nb.y; ++by) {
      const int y0 = by * kBrickEdge, z0 = bz * kBrickEdge;
      const int y1 = std::min(y0 + kBrickEdge, n.y), z1 = std::min(z0 + kBrickEdge, n.z);
      // Bricks past the volume's edge keep their padding empty.
      if (y1 - y0 < kBrickEdge || z1 - z0 < kBrickEdge || n.x % kBrickEdge != 0) {
        for (auto& f : fill) f.fill(0);
        for (auto& d : density) d.fill(0);
      }
      for (int z = z0; z < z1; ++z) {
        for (int y = y0; y < y1; ++y) {
          std::size_t i = (std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x);
          const int row = kBrickEdge * ((y - y0) + kBrickEdge * (z - z0));
          for (int x = 0; x < n.x; ++x, ++i) {
            const std::size_t bx = std::size_t(x / kBrickEdge);
            const std::size_t local = std::size_t(row + x % kBrickEdge);
            voxel(glm::ivec3(x, y, z), i, fill[bx][local], density[bx][local]);
          }
        }
      }
      for (int bx = 0; bx < nb.x; ++bx) {
        const auto& f = fill[std::size_t(bx)];
        const auto& d = density[std::size_t(bx)];
        bool uniform = true;
        for (std::size_t local = 0; local < kBrickVoxels; ++local) {
          inside += f[local] >= kFillHalf;
          uniform = uniform && f[local] == f[0] && d[local] == d[0];
        }
        const std::size_t brick = grid.brickIndex({bx, by, bz});
        if (uniform) {
          grid.setBrickUniform(brick, f[0], d[0]);
          continue;
        }
        VoxelGrid::Brick& b = grid.materialiseBrick(brick);
        b.fill = f;
        b.density = d;
      }
    }
  }
  grid.clearDirty();
  return inside;
}

}  // namespace osteon::geometry
