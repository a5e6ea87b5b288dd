#include "surface_cells.h"

#include <algorithm>
#include <chrono>

#include <glm/geometric.hpp>

#include "osteon/core/timing.h"

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

// Which sides (bit 0 outside, bit 1 inside) the parts of a grid brick a cell brick can read
// hold, two bits per part, part d read by the cell brick below it at octant d: the whole
// brick (d = 0), its x = 0 face (1), y = 0 face (2), x = y = 0 line (3), z = 0 face (4),
// x = z = 0 line (5), y = z = 0 line (6), its first voxel (7).
constexpr std::uint16_t kAllOutside = 0x5555, kAllInside = 0xaaaa;

std::uint16_t partSides(const Fill* fill, std::uint8_t* rowBits) {
  // Rows of eight inside bits (x), 64 of them (y + 8 z), kept in rowBits for pass 1; the
  // sides of each part from the rows' union and intersection over the rows the part lies in.
#if defined(__SSE2__)
  // The union and intersection taken over the rows' compare masks (one 16-bit lane per x),
  // turned into bits once per part rather than once per row.
  const __m128i threshold = _mm_set1_epi16(std::int16_t(kInsideAbove));
  const auto inside = [&](int row) {
    return _mm_cmpgt_epi16(
        _mm_loadu_si128(reinterpret_cast<const __m128i*>(fill + kCellBrick * row)), threshold);
  };
  const auto bits = [](__m128i m) {
    return std::uint32_t(_mm_movemask_epi8(_mm_packs_epi16(m, _mm_setzero_si128()))) & 0xffu;
  };
  // Each row's inside bits, two rows at a time, for pass 1's cell cases.
  const auto twoRows = [&](int row, __m128i m0, __m128i m1) {
    const auto bits16 = std::uint16_t(_mm_movemask_epi8(_mm_packs_epi16(m0, m1)));
    std::memcpy(rowBits + row, &bits16, 2);
  };
  __m128i anyZ = _mm_setzero_si128(), allZ = _mm_set1_epi16(-1);
  for (int row = 0; row < kCellBrick; row += 2) {  // z = 0
    const __m128i m0 = inside(row), m1 = inside(row + 1);
    anyZ = _mm_or_si128(anyZ, _mm_or_si128(m0, m1));
    allZ = _mm_and_si128(allZ, _mm_and_si128(m0, m1));
    twoRows(row, m0, m1);
  }
  __m128i anyB = anyZ, allB = allZ, anyY = _mm_setzero_si128(), allY = _mm_set1_epi16(-1);
  for (int z = 0; z < kCellBrick; ++z) {
    const __m128i m = inside(kCellBrick * z);  // y = 0
    anyY = _mm_or_si128(anyY, m);
    allY = _mm_and_si128(allY, m);
  }
  for (int row = kCellBrick; row < kCellBrick * kCellBrick; row += 2) {
    const __m128i m0 = inside(row), m1 = inside(row + 1);
    anyB = _mm_or_si128(anyB, _mm_or_si128(m0, m1));
    allB = _mm_and_si128(allB, _mm_and_si128(m0, m1));
    twoRows(row, m0, m1);
  }
  const std::uint32_t anyAll = bits(anyB), allAll = bits(allB), anyZ0 = bits(anyZ),
                      allZ0 = bits(allZ);
  const std::uint32_t anyY0 = bits(anyY), allY0 = bits(allY), row0 = bits(inside(0));
#else
  std::uint32_t anyAll = 0, allAll = 0xff, anyZ0 = 0, allZ0 = 0xff, anyY0 = 0, allY0 = 0xff;
  for (int z = 0; z < kCellBrick; ++z)
    for (int y = 0; y < kCellBrick; ++y) {
      const std::uint32_t row = insideOf8(fill + kCellBrick * (y + kCellBrick * z));
      rowBits[y + kCellBrick * z] = std::uint8_t(row);
      anyAll |= row;
      allAll &= row;
      if (z == 0) {
        anyZ0 |= row;
        allZ0 &= row;
      }
      if (y == 0) {
        anyY0 |= row;
        allY0 &= row;
      }
    }
  const std::uint32_t row0 = insideOf8(fill);
#endif
  // Sides of a set of voxels whose inside bits are `any` (union) and `all` (intersection)
  // over the bits in `mask`.
  const auto sides = [](std::uint32_t any, std::uint32_t all, std::uint32_t mask) {
    return ((all & mask) != mask ? 1u : 0u) | ((any & mask) != 0 ? 2u : 0u);
  };
  const std::uint32_t parts[8] = {sides(anyAll, allAll, 0xff), sides(anyAll, allAll, 1),
                                  sides(anyY0, allY0, 0xff),   sides(anyY0, allY0, 1),
                                  sides(anyZ0, allZ0, 0xff),   sides(anyZ0, allZ0, 1),
                                  sides(row0, row0, 0xff),     sides(row0, row0, 1)};
  std::uint16_t packed = 0;
  for (int d = 0; d < 8; ++d) packed = std::uint16_t(packed | (parts[d] << (2 * d)));
  return packed;
}

// Asks for a stored brick's fills two bricks ahead of reading them: bricks are separate
// allocations, so the hardware's stream prefetch would start afresh at each after a miss or two.
void prefetchFills(const VoxelGrid::Brick* brick) {
  if (!brick) return;
  const char* p = reinterpret_cast<const char*>(brick->fill.data());
  for (std::size_t off = 0; off < sizeof(brick->fill); off += 64) __builtin_prefetch(p + off);
}

}  // namespace

ActiveBrickScan::ActiveBrickScan(const VoxelGrid& grid, std::vector<std::uint16_t>& states,
                                 std::vector<RowBits>& rowBits)
    : grid_(grid), states_(states), rowBits_(rowBits), e_(grid.brickDims() + 2) {
  // Two layers of grid-brick states, bricks -1 .. nb along x and y; layer z + 1 at
  // ((z + 1) & 1). Layer -1 lies wholly outside the grid.
  states_.resize(2 * layerSize());
  std::fill_n(states_.begin(), layerSize(), kAllOutside);
  rowBits_.resize(2 * layerSize());
  std::fill_n(rowBits_.begin(), layerSize(), RowBits{});
}

void ActiveBrickScan::computeLayer(int z) {
  // What the parts of the layer's bricks hold (the border reads as empty), each brick read
  // once, as the slab of cell bricks that reads it last is about to be scanned.
  const glm::ivec3 nb = grid_.brickDims();
  std::uint16_t* layer = states_.data() + std::size_t((z + 1) & 1) * layerSize();
  RowBits* bitsLayer = rowBits_.data() + std::size_t((z + 1) & 1) * layerSize();
  for (int y = -1; y <= nb.y; ++y)
    for (int x = -1; x <= nb.x; ++x) {
      std::uint16_t state = kAllOutside;
      const std::size_t at = std::size_t(x + 1) + std::size_t(e_.x) * std::size_t(y + 1);
      RowBits& bits = bitsLayer[at];
      if (x >= 0 && y >= 0 && z >= 0 && x < nb.x && y < nb.y && z < nb.z) {
        const std::size_t i = grid_.brickIndex({x, y, z});
        if (i + 2 < grid_.brickCount())
          prefetchFills(grid_.brickData(i + 2));  // across row ends too
        if (const VoxelGrid::Brick* brick = grid_.brickData(i)) {
          state = partSides(brick->fill.data(), bits.data());
        } else if (double(grid_.brickUniformFill(i)) > kIso) {
          state = kAllInside;
        }
      }
      if (state == kAllOutside || state == kAllInside) bits.fill(state == kAllInside ? 0xff : 0);
      layer[at] = state;
    }
}

void ActiveBrickScan::slab(int z, std::vector<glm::ivec3>& active) {
  // A cell brick reads all of its own brick and only a face, line or voxel of the seven above
  // it, so it can hold surface only if those hold both sides: tighter than "not all eight
  // uniform alike", which admits many bricks without a mixed cell (a brick with any fill
  // between empty and full is stored as an array, as on a voxelized sphere).
  computeLayer(z + 1);
  const std::uint16_t* layers[2] = {states_.data() + std::size_t((z + 1) & 1) * layerSize(),
                                    states_.data() + std::size_t((z + 2) & 1) * layerSize()};
  for (int y = 0; y + 1 < e_.y; ++y)
    for (int x = 0; x + 1 < e_.x; ++x) {
      std::uint32_t sides = 0;
      for (int d = 0; d < 8; ++d) {
        const std::uint16_t* layer = layers[(d >> 2) & 1];
        const std::size_t at =
            std::size_t(x + (d & 1)) + std::size_t(e_.x) * std::size_t(y + ((d >> 1) & 1));
        sides |= std::uint32_t(layer[at] >> (2 * d)) & 3u;
      }
      if (sides == 3) active.push_back({x - 1, y - 1, z});
    }
}

// A cell brick can hold surface when the eight bricks its cells read (octant d: +x if d & 1,
// +y if d & 2, +z if d & 4) are not one uniform state.
bool cellBrickActive(const VoxelGrid& grid, const glm::ivec3& cb) {
  const int first = brickState(grid, cb);
  if (first == 2) return true;
  for (int d = 1; d < 8; ++d) {
    if (brickState(grid, cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1)) != first) return true;
  }
  return false;
}

void BlockSource::init(const VoxelGrid& grid, const glm::ivec3& cb) {
  const glm::ivec3 nb = grid.brickDims();
  const glm::ivec3 base = cb * kCellBrick;
  lo = glm::max(-base, glm::ivec3(0));
  hi = glm::min(grid.dims() - base, glm::ivec3(kBlock));
  for (int d = 0; d < 8; ++d) {
    const glm::ivec3 b = cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1);
    data[std::size_t(d)] = nullptr;
    uniform[std::size_t(d)] = 0;
    if (b.x < 0 || b.y < 0 || b.z < 0 || b.x >= nb.x || b.y >= nb.y || b.z >= nb.z) continue;
    const std::size_t brick = grid.brickIndex(b);
    if (const VoxelGrid::Brick* brickData = grid.brickData(brick)) {
      data[std::size_t(d)] = brickData->fill.data();
    } else {
      uniform[std::size_t(d)] = grid.brickUniformFill(brick);
    }
  }
  // Empty and full uniform bricks (nearly all of them) read as constant arrays, so most
  // blocks read every row the same way.
  static const std::array<Fill, VoxelGrid::kBrickVoxels> kEmpty{};
  static const std::array<Fill, VoxelGrid::kBrickVoxels> kFull = [] {
    std::array<Fill, VoxelGrid::kBrickVoxels> b;
    b.fill(kFillFull);
    return b;
  }();
  // Reads outside the grid come from bricks wholly outside it (the empty array), so they need
  // no clipping: below the grid always (brick -1), above it when the grid's size along that
  // axis is a whole number of bricks (else the last brick's voxels past the end would be read).
  const glm::ivec3 dims = grid.dims();
  dense = true;
  for (int k = 0; k < 3; ++k) {
    if (hi[k] < kBlock && dims[k] % kCellBrick != 0) dense = false;
  }
  for (std::size_t d = 0; d < 8; ++d) {
    if (data[d]) continue;
    if (uniform[d] == 0) {
      data[d] = kEmpty.data();
    } else if (uniform[d] == kFillFull) {
      data[d] = kFull.data();
    } else {
      dense = false;
    }
  }
}

void loadBlock(const VoxelGrid& grid, const glm::ivec3& cb, FillBlock& block) {
  // A row at a time from the bricks (BlockSource::row), 0 outside the grid.
  BlockSource src;
  src.init(grid, cb);
  for (int z = 0; z < kBlock; ++z)
    for (int y = 0; y < kBlock; ++y) src.row(y, z, block.data() + kBlock * (y + kBlock * z));
}

void cellRange(const VoxelGrid& grid, const glm::ivec3& cb, glm::ivec3& lo, glm::ivec3& hi) {
  lo = glm::max(cb * kCellBrick, glm::ivec3(-1));
  hi = glm::min(cb * kCellBrick + kCellBrick, grid.dims());  // cells -1 .. dims-1
}

namespace {

void placeCentres(const Buffer<VertexInfo>& info, const Buffer<std::uint32_t>& loops,
                  Buffer<glm::dvec3>& positions) {
  for (std::size_t i = 0; i < info.size(); ++i) {
    if (info[i].axis != 3) continue;
    glm::dvec3 sum(0.0);
    for (std::uint32_t k = 0; k < info[i].loopCount; ++k)
      sum += positions[loops[info[i].loopFirst + k]];
    positions[i] = sum / double(info[i].loopCount);
  }
}

// Neighbours of every vertex through the triangles (compressed rows, duplicates removed).
void buildAdjacency(std::size_t n, const Buffer<glm::u32vec3>& triangles,
                    std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& neighbours) {
  std::vector<std::uint32_t> degree(n + 1, 0);
  for (const glm::u32vec3& t : triangles) {
    for (int c = 0; c < 3; ++c) degree[t[c] + 1] += 2;
  }
  start.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) start[i + 1] = start[i] + degree[i + 1];
  neighbours.assign(start[n], 0);
  std::vector<std::uint32_t> fillAt(start.begin(), start.end() - 1);
  for (const glm::u32vec3& t : triangles) {
    for (int c = 0; c < 3; ++c) {
      neighbours[fillAt[t[c]]++] = t[(c + 1) % 3];
      neighbours[fillAt[t[c]]++] = t[(c + 2) % 3];
    }
  }
  // Sort and unique each row in place, then compact.
  std::uint32_t out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    auto b = neighbours.begin() + start[i];
    auto e = neighbours.begin() + start[i + 1];
    std::sort(b, e);
    e = std::unique(b, e);
    const std::uint32_t rowStart = out;
    for (auto it = b; it != e; ++it) neighbours[out++] = *it;
    start[i] = rowStart;
  }
  start[n] = out;
  neighbours.resize(out);
}

}  // namespace

void areaWeightedNormals(const Buffer<glm::dvec3>& positions, const Buffer<glm::u32vec3>& triangles,
                         Buffer<glm::dvec3>& normals) {
  normals.assign(positions.size(), glm::dvec3(0.0));
  for (const glm::u32vec3& t : triangles) {
    const glm::dvec3& a = positions[t.x];
    // The cross product's length is twice the area: area weighting for free.
    const glm::dvec3 w = glm::cross(positions[t.y] - a, positions[t.z] - a);
    normals[t.x] += w;
    normals[t.y] += w;
    normals[t.z] += w;
  }
  for (glm::dvec3& nrm : normals) {
    const double len = glm::length(nrm);
    nrm = len > 0.0 ? nrm / len : glm::dvec3(0.0);
  }
}

void finishSurface(Buffer<VertexInfo>& vertices, const Buffer<std::uint32_t>& loopVertices,
                   Buffer<glm::u32vec3>& triangles, const SurfaceOptionsView& options,
                   Buffer<glm::dvec3>& positions, Buffer<glm::dvec3>& normals, double& otherMs,
                   double& smoothMs, double& normalsMs) {
  Clock::time_point phase = Clock::now();
  const std::size_t n = vertices.size();
  positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (vertices[i].axis != 3) positions[i] = positionOf(vertices[i]);
  }
  placeCentres(vertices, loopVertices, positions);
  std::vector<std::uint32_t> rowStart, neighbours;
  if (options.smoothIterations > 0) buildAdjacency(n, triangles, rowStart, neighbours);
  otherMs += msSince(phase);

  // Laplacian passes (Jacobi): each edge vertex moves only along its own grid edge, towards
  // its neighbours' mean, and stays inside the edge, so no triangle can fold over another.
  phase = Clock::now();
  std::vector<double> newT(n);
  for (int pass = 0; pass < options.smoothIterations; ++pass) {
    const double step = options.taubin && pass % 2 == 1 ? options.mu : options.lambda;
    for (std::size_t i = 0; i < n; ++i) {
      const VertexInfo& v = vertices[i];
      if (v.axis == 3) continue;
      const std::uint32_t b = rowStart[i];
      const std::uint32_t e = rowStart[i + 1];
      double mean = 0.0;
      for (std::uint32_t k = b; k < e; ++k) mean += positions[neighbours[k]][v.axis];
      mean /= double(e - b);
      const double t = v.t + step * (mean - positions[i][v.axis]) / v.lengthMm;
      newT[i] = std::clamp(t, kEdgeMargin, 1.0 - kEdgeMargin);
    }
    for (std::size_t i = 0; i < n; ++i) {
      VertexInfo& v = vertices[i];
      if (v.axis == 3) continue;
      v.t = newT[i];
      positions[i] = positionOf(v);
    }
    placeCentres(vertices, loopVertices, positions);
  }
  smoothMs += msSince(phase);

  phase = Clock::now();
  normals.clear();
  if (options.computeNormals) areaWeightedNormals(positions, triangles, normals);
  normalsMs += msSince(phase);
}

}  // namespace osteon::geometry::detail
