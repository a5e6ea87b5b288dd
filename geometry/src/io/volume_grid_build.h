// Building a volume's VoxelGrid (volume_load.cpp): a row of bricks at a time in parallel, and
// the deep inside voxels the density rule of label maps and scalar volumes needs.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "io/huge_pages.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

// Calls f(position, index) for every voxel, slices in parallel (f must allow that).
template <typename F>
void forEachVoxel(glm::ivec3 n, const F& f) {
  tbb::parallel_for(tbb::blocked_range<int>(0, n.z), [&](const tbb::blocked_range<int>& zs) {
    for (int z = zs.begin(); z < zs.end(); ++z) {
      std::size_t i = std::size_t(z) * std::size_t(n.y) * std::size_t(n.x);
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x, ++i) f(glm::ivec3(x, y, z), i);
    }
  });
}

// The erosions deepInside runs, in place on 0/1 bytes: a voxel stays 1 when the 2 r + 1 voxels
// centred on it along the line are all 1 and within it. A run count along the line: linear in
// its length whatever r is.
inline void erodeRow(std::uint8_t* line, std::size_t length, int r) {
  const std::size_t edge = std::size_t(r);
  std::uint8_t* const end = line + length;
  // Run by run (memchr finds their ends a vector at a time): a run of ones keeps all but its
  // first and last r voxels.
  for (std::uint8_t* p = line; p < end;) {
    auto* first = static_cast<std::uint8_t*>(std::memchr(p, 1, std::size_t(end - p)));
    if (!first) break;
    auto* last = static_cast<std::uint8_t*>(std::memchr(first, 0, std::size_t(end - first)));
    if (!last) last = end;
    const std::size_t head = std::min(edge, std::size_t(last - first));
    const std::size_t tail = std::min(edge, std::size_t(last - first) - head);
    std::fill_n(first, head, std::uint8_t(0));
    std::fill_n(last - tail, tail, std::uint8_t(0));
    p = last;
  }
}

// The same across `length` rows of `width` bytes `stride` apart, all columns at once (the inner
// loops run along memory and vectorise); `run` is the caller's scratch. Runs count in bytes,
// saturating, while the window fits one (a run at 255 is still at least the window): 16 columns
// a vector instead of 4.
template <typename Count>
void erodeAcrossCounting(std::uint8_t* base, std::size_t stride, int length, std::size_t width,
                         int r, std::vector<Count>& run) {
  const auto window = Count(2 * r + 1);
  constexpr Count kMost = std::numeric_limits<Count>::max();
  run.assign(width, 0);
  Count* const counts = run.data();  // a local: byte stores may alias the vector's
  for (int k = 0; k < length; ++k) {
    const std::uint8_t* row = base + std::size_t(k) * stride;
    for (std::size_t x = 0; x < width; ++x) {
      const Count next = counts[x] == kMost ? kMost : Count(counts[x] + 1);
      counts[x] = row[x] != 0 ? next : Count(0);
    }
    if (k < r) continue;
    std::uint8_t* out = base + std::size_t(k - r) * stride;
    for (std::size_t x = 0; x < width; ++x) out[x] = std::uint8_t(counts[x] >= window);
  }
  for (int k = std::max(0, length - r); k < length; ++k)
    std::fill_n(base + std::size_t(k) * stride, width, std::uint8_t(0));
}

struct RunScratch {
  std::vector<std::uint8_t> bytes;
  std::vector<std::int32_t> wide;
};

inline void erodeAcross(std::uint8_t* base, std::size_t stride, int length, std::size_t width,
                        int r, RunScratch& run) {
  if (2 * r + 1 <= 255) {
    erodeAcrossCounting(base, stride, length, width, r, run.bytes);
  } else {
    erodeAcrossCounting(base, stride, length, width, r, run.wide);
  }
}

// 1 where a voxel lies deeper than `shell` voxels inside: every voxel within chessboard distance
// `shell` of it (the (2 shell + 1)^3 cube around it) is inside (fill at or above half) and within
// the volume; 0 elsewhere. fillRow(start, index, length, fills) gives a row's fills. A cube is
// the product of three segments, so three erosions along the axes: x and y slice by slice, then
// z a slab of kBrickEdge rows at a time, each in parallel. One byte per voxel: a deeper voxel's
// distance is never needed.
template <typename FillRow>
std::unique_ptr<std::uint8_t[]> deepInside(glm::ivec3 n, int shell, const FillRow& fillRow) {
  const std::size_t nx = std::size_t(n.x), slice = nx * std::size_t(n.y);
  // Not zeroed first: every byte is written by its slice's task (its pages touched there too).
  std::unique_ptr<std::uint8_t[]> deep(new std::uint8_t[slice * std::size_t(n.z)]);
  adviseHugePages(deep.get(), slice * std::size_t(n.z));
  tbb::parallel_for(tbb::blocked_range<int>(0, n.z), [&](const tbb::blocked_range<int>& zs) {
    RunScratch run;
    std::vector<Fill> fills(nx);
    const Fill* const fill = fills.data();
    const std::size_t width = nx;  // locals: byte stores may alias what a reference reaches
    for (int z = zs.begin(); z < zs.end(); ++z) {
      std::uint8_t* s = deep.get() + std::size_t(z) * slice;
      for (int y = 0; y < n.y; ++y) {
        std::uint8_t* row = s + std::size_t(y) * nx;
        fillRow(glm::ivec3(0, y, z), std::size_t(z) * slice + std::size_t(y) * width, n.x,
                fills.data());
        for (std::size_t x = 0; x < width; ++x) row[x] = std::uint8_t(fill[x] >= kFillHalf);
        erodeRow(row, width, shell);
      }
      erodeAcross(s, width, n.y, width, shell, run);
    }
  });
  const int slabs = (n.y + kBrickEdge - 1) / kBrickEdge;
  tbb::parallel_for(tbb::blocked_range<int>(0, slabs), [&](const tbb::blocked_range<int>& ys) {
    RunScratch run;
    for (int slab = ys.begin(); slab < ys.end(); ++slab) {
      const int y0 = slab * kBrickEdge, rows = std::min(kBrickEdge, n.y - y0);
      erodeAcross(deep.get() + std::size_t(y0) * nx, slice, n.z, nx * std::size_t(rows), shell,
                  run);
    }
  });
  return deep;
}

// A row of bricks as the volume lies (x fastest over the whole row, then y, then z), padded to
// whole bricks with empty voxels.
struct BrickRow {
  std::size_t stride;  // voxels from one y to the next: the row's bricks times kBrickEdge
  std::vector<Fill> fill;
  std::vector<Density> density;
  explicit BrickRow(int bricks)
      : stride(std::size_t(bricks) * std::size_t(kBrickEdge)),
        fill(stride * kBrickEdge * kBrickEdge),
        density(fill.size()) {}
  std::size_t at(int x, int y, int z) const {
    return (std::size_t(z) * kBrickEdge + std::size_t(y)) * stride + std::size_t(x);
  }
};

// Whether the kBrickEdge values at `at` all equal `first`: compared 8 bytes at a time.
template <typename T>
inline bool rowEquals(const T* at, T first) {
  static_assert(kBrickEdge * sizeof(T) % 8 == 0, "whole 64-bit words a brick row");
  constexpr int kWords = int(kBrickEdge * sizeof(T) / 8);
  std::array<T, 8 / sizeof(T)> pattern;
  pattern.fill(first);
  std::uint64_t word = 0, differs = 0;
  std::memcpy(&word, pattern.data(), 8);
  for (int k = 0; k < kWords; ++k) {
    std::uint64_t w = 0;
    std::memcpy(&w, reinterpret_cast<const unsigned char*>(at) + 8 * k, 8);
    differs |= w ^ word;
  }
  return differs == 0;
}

// Stores brick bx of a row: one whose voxels all agree stays unallocated (a volume's air and
// deep bone cost no voxel arrays). Returns its voxels inside (fill at or above half), counted
// only where they differ: padding past the volume's edge is empty, so a uniform brick that is
// inside lies wholly within the volume.
inline std::uint64_t storeBrick(VoxelGrid& grid, std::size_t brick, const BrickRow& row, int bx) {
  const int x0 = bx * kBrickEdge;
  const Fill f0 = row.fill[row.at(x0, 0, 0)];
  const Density d0 = row.density[row.at(x0, 0, 0)];
  bool uniform = true;
  for (int z = 0; z < kBrickEdge && uniform; ++z) {
    for (int y = 0; y < kBrickEdge && uniform; ++y) {
      uniform = rowEquals(&row.fill[row.at(x0, y, z)], f0) &&
                rowEquals(&row.density[row.at(x0, y, z)], d0);
    }
  }
  if (uniform) {
    grid.setBrickUniform(brick, f0, d0);  // on a new grid: no brick to release
    return f0 >= kFillHalf ? kBrickVoxels : 0;
  }
  VoxelGrid::Brick& b = grid.materialiseBrick(brick);
  std::uint32_t inside = 0;
  for (int z = 0; z < kBrickEdge; ++z) {
    for (int y = 0; y < kBrickEdge; ++y) {
      const std::size_t from = row.at(x0, y, z);
      const auto to = std::ptrdiff_t(VoxelGrid::voxelInBrick({0, y, z}));
      std::copy_n(row.fill.begin() + std::ptrdiff_t(from), kBrickEdge, b.fill.begin() + to);
      std::copy_n(row.density.begin() + std::ptrdiff_t(from), kBrickEdge, b.density.begin() + to);
    }
  }
  for (const Fill f : b.fill) inside += f >= kFillHalf;
  return inside;
}

// Sets every voxel of a new grid from voxelRow(start, index, length, fills, densities), which
// gives a row of voxels at once (x from start.x): rows of bricks in parallel, each visited in
// storage order (the values are read as they lie in memory), then its bricks stored. voxelRow
// must be safe to call from several threads. Returns the voxels inside (fill at or above half).
template <typename VoxelRow>
std::uint64_t buildGrid(VoxelGrid& grid, const VoxelRow& voxelRow) {
  const glm::ivec3 n = grid.dims(), nb = grid.brickDims();
  std::atomic<std::uint64_t> inside{0};
  tbb::parallel_for(
      tbb::blocked_range<int>(0, nb.y * nb.z), [&](const tbb::blocked_range<int>& rs) {
        BrickRow row(nb.x);
        std::uint64_t rowsInside = 0;
        for (int r = rs.begin(); r < rs.end(); ++r) {
          const int by = r % nb.y, bz = r / nb.y;
          const int y0 = by * kBrickEdge, z0 = bz * kBrickEdge;
          const int y1 = std::min(y0 + kBrickEdge, n.y), z1 = std::min(z0 + kBrickEdge, n.z);
          // Rows past the volume's edge stay empty (x past it is never written).
          if (y1 - y0 < kBrickEdge || z1 - z0 < kBrickEdge) {
            std::fill(row.fill.begin(), row.fill.end(), Fill(0));
            std::fill(row.density.begin(), row.density.end(), Density(0));
          }
          for (int z = z0; z < z1; ++z) {
            for (int y = y0; y < y1; ++y) {
              const std::size_t i =
                  (std::size_t(z) * std::size_t(n.y) + std::size_t(y)) * std::size_t(n.x);
              const std::size_t at = row.at(0, y - y0, z - z0);
              voxelRow(glm::ivec3(0, y, z), i, n.x, &row.fill[at], &row.density[at]);
            }
          }
          for (int bx = 0; bx < nb.x; ++bx)
            rowsInside += storeBrick(grid, grid.brickIndex({bx, by, bz}), row, bx);
        }
        inside += rowsInside;
      });
  grid.clearDirty();
  return inside.load();
}

}  // namespace osteon::geometry
