// The cell-level pieces of surface extraction shared by the full extractor and the
// incremental updater: which cell bricks can hold surface, reading a brick's fills, making a
// vertex on a crossed edge, and the case of one cell.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/vec3.hpp>

#include "mc_table.h"
#include "osteon/geometry/surface/buffer.h"
#include "osteon/geometry/voxels/voxel_grid.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace osteon::geometry::detail {

inline constexpr int kCellBrick = kBrickEdge;  // cells per cell-brick edge
inline constexpr int kBlock = kCellBrick + 1;  // voxels a cell brick reads per edge
// Between two integers, so no fill value sits exactly on the iso level.
inline constexpr double kIso = double(kFillHalf) - 0.5;
// Vertices stay this far (in voxels) from the cube corners: no coincident vertices, no
// zero-area triangles, whatever the fills and the smoothing.
inline constexpr double kEdgeMargin = 1e-3;
inline constexpr std::uint32_t kNoVertex = 0xffffffffu;

using FillBlock = std::array<Fill, kBlock * kBlock * kBlock>;

// fill > this <=> fill > kIso (fills are integers, kIso sits halfway between two).
inline constexpr Fill kInsideAbove = Fill(kFillHalf - 1);

// Inside bits of eight fills in a row.
inline std::uint32_t insideOf8(const Fill* f) {
#if defined(__SSE2__)
  // Fills are at most 16320, so the signed 16-bit compare is exact.
  const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(f));
  const __m128i inside = _mm_cmpgt_epi16(v, _mm_set1_epi16(std::int16_t(kInsideAbove)));
  return std::uint32_t(_mm_movemask_epi8(_mm_packs_epi16(inside, _mm_setzero_si128()))) & 0xffu;
#else
  std::uint32_t m = 0;
  for (int x = 0; x < kCellBrick; ++x) m |= (f[x] > kInsideAbove ? 1u : 0u) << x;
  return m;
#endif
}

inline int floorDiv(int a, int b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

// A vertex: on a grid edge (axis 0..2, parameter t from the edge's first voxel centre), or the
// centre of a long loop (axis 3), which follows the loop's vertices.
struct VertexInfo {
  glm::dvec3 edgeStartMm;
  int axis;
  double t;
  double lengthMm;          // edge vertices: the edge's length (a voxel, or a finer sample)
  std::uint32_t loopFirst;  // centre vertices: the loop's vertices
  std::uint32_t loopCount;
  glm::ivec3 voxel;  // edge vertices: the edge's first voxel; centres: their cell
};

inline glm::dvec3 positionOf(const VertexInfo& v) {
  glm::dvec3 p = v.edgeStartMm;
  p[v.axis] += v.t * v.lengthMm;
  return p;
}

// After extraction: positions, edge-constrained smoothing (Laplacian or Taubin; each edge
// vertex moves only along its own edge, loop centres follow their loop's mean) and
// area-weighted normals. Moves `triangles` into `mesh`; adds to the timings.
struct SurfaceOptionsView {
  int smoothIterations;
  double lambda;
  bool taubin;
  double mu;
  bool computeNormals;
};
void finishSurface(Buffer<VertexInfo>& vertices, const Buffer<std::uint32_t>& loopVertices,
                   Buffer<glm::u32vec3>& triangles, const SurfaceOptionsView& options,
                   Buffer<glm::dvec3>& positions, Buffer<glm::dvec3>& normals, double& otherMs,
                   double& smoothMs, double& normalsMs);

// Unit normals, each the sum of its triangles' area-weighted normals.
void areaWeightedNormals(const Buffer<glm::dvec3>& positions, const Buffer<glm::u32vec3>& triangles,
                         Buffer<glm::dvec3>& normals);

// Where a cell brick's 9^3 block of fills comes from, read in place: the up to eight grid
// bricks it overlaps (octant d: +x if d & 1, +y if d & 2, +z if d & 4), each an array or one
// uniform value, and the block coordinates that lie in the grid ([lo, hi) per axis; outside it
// every fill is 0, so the surface closes at the border). The full extractor reads through it;
// loadBlock copies through it.
struct BlockSource {
  std::array<const Fill*, 8> data;  // uniform empty and full bricks point at constant arrays
  std::array<Fill, 8> uniform;
  glm::ivec3 lo, hi;
  bool dense;  // every brick an array, nothing to clip: rows read without checks

  void init(const VoxelGrid& grid, const glm::ivec3& cellBrick);
  // Fills of block row (y, z), x = 0..8, into out[0..8]: the first eight one brick row (a
  // fixed-size copy the compiler inlines, not a library call per row), the ninth the next
  // brick's along x; 0 outside the grid.
  void row(int y, int z, Fill* out) const {
    const auto d = std::size_t(((y >> 3) << 1) | ((z >> 3) << 2));
    const int offset = kCellBrick * ((y & 7) + kCellBrick * (z & 7));
    if (dense) {
      std::memcpy(out, data[d] + offset, kCellBrick * sizeof(Fill));
      out[kCellBrick] = data[d | 1][offset];
      return;
    }
    if (y < lo.y || y >= hi.y || z < lo.z || z >= hi.z) {
      std::fill_n(out, kBlock, Fill(0));
      return;
    }
    if (data[d]) {
      std::memcpy(out, data[d] + offset, kCellBrick * sizeof(Fill));
    } else {
      std::fill_n(out, kCellBrick, uniform[d]);
    }
    out[kCellBrick] = data[d | 1] ? data[d | 1][offset] : uniform[d | 1];
    for (int x = 0; x < lo.x; ++x) out[x] = 0;
    for (int x = hi.x; x < kBlock; ++x) out[x] = 0;
  }
  Fill at(int x, int y, int z) const {  // block coordinates 0..8
    if (x < lo.x || y < lo.y || z < lo.z || x >= hi.x || y >= hi.y || z >= hi.z) return 0;
    const auto d = std::size_t((x >> 3) | ((y >> 3) << 1) | ((z >> 3) << 2));
    const Fill* f = data[d];
    return f ? f[(x & 7) + kCellBrick * ((y & 7) + kCellBrick * (z & 7))] : uniform[d];
  }
};

// Cells are numbered by their first voxel, from -1 (the border layer outside the grid) to
// dims - 1; cell brick cb holds cells cb * 8 .. cb * 8 + 7.
// Two tests, each admitting every cell brick with a mixed cell. cellBrickActive, for one brick
// (the incremental updater, the multi-resolution extractor): its eight grid bricks are not all
// uniform alike; it reads no fills.
bool cellBrickActive(const VoxelGrid& grid, const glm::ivec3& cellBrick);
// ActiveBrickScan, for the whole grid (the full extractor): tighter, each stored grid brick's
// fills read once for the sides the parts a cell brick reads of it hold, slab by slab (a z
// layer of cell bricks), so a caller can work on a slab while its bricks are in cache.
class ActiveBrickScan {
 public:
  // Rows of inside bits of a grid brick: byte y + 8 z, bit x.
  using RowBits = std::array<std::uint8_t, VoxelGrid::kBrickSize * VoxelGrid::kBrickSize>;
  // states, rowBits: scratch (two layers of grid-brick states and their rows' inside bits).
  ActiveBrickScan(const VoxelGrid& grid, std::vector<std::uint16_t>& states,
                  std::vector<RowBits>& rowBits);
  // Appends the active cell bricks of slab z (-1 .. brickDims().z - 1) in y, x order; slabs
  // are scanned in increasing z, each once.
  void slab(int z, std::vector<glm::ivec3>& active);
  // The inside bits of grid brick b's rows (zero outside the grid, every bit set in a full
  // brick), for the bricks the last slab's cell bricks read (layers z and z + 1).
  const RowBits& rowBits(const glm::ivec3& b) const {
    return rowBits_[std::size_t((b.z + 1) & 1) * layerSize() + std::size_t(b.x + 1) +
                    std::size_t(e_.x) * std::size_t(b.y + 1)];
  }

 private:
  std::size_t layerSize() const { return std::size_t(e_.x) * std::size_t(e_.y); }
  void computeLayer(int z);
  const VoxelGrid& grid_;
  std::vector<std::uint16_t>& states_;
  std::vector<RowBits>& rowBits_;
  glm::ivec3 e_;  // grid bricks -1 .. nb per axis
};
void loadBlock(const VoxelGrid& grid, const glm::ivec3& cellBrick, FillBlock& block);
void cellRange(const VoxelGrid& grid, const glm::ivec3& cellBrick, glm::ivec3& lo, glm::ivec3& hi);

// Where the iso level crosses an edge whose ends hold fills a and b, as a fraction of the edge.
inline double edgeParameter(Fill a, Fill b) {
  const double t = (kIso - double(a)) / (double(b) - double(a));
  return std::max(kEdgeMargin, std::min(t, 1.0 - kEdgeMargin));  // never NaN: a != b
}

inline VertexInfo edgeVertexInfo(const VoxelGrid& grid, const glm::ivec3& voxel, int axis, Fill a,
                                 Fill b) {
  return {grid.voxelCentreMm(voxel), axis, edgeParameter(a, b), grid.voxelSizeMm(), 0, 0, voxel};
}

inline Fill blockFill(const FillBlock& block, int x, int y, int z) {
  return block[std::size_t(x + kBlock * (y + kBlock * z))];
}

// Inside bits of a block, one 9-bit word per (y, z) row (bit x: voxel x is inside), so whole
// rows of cells with no crossing are skipped with a few word operations.
using RowMasks = std::array<std::uint16_t, kBlock * kBlock>;

// The four corner rows of a row of cells (inside bits by x): its own, +y, +z, +y+z.
inline void rowCorners(const RowMasks& rows, int ly, int lz, std::uint32_t (&r)[4]) {
  r[0] = rows[std::size_t(ly + kBlock * lz)];
  r[1] = rows[std::size_t(ly + 1 + kBlock * lz)];
  r[2] = rows[std::size_t(ly + kBlock * (lz + 1))];
  r[3] = rows[std::size_t(ly + 1 + kBlock * (lz + 1))];
}

// Every cell's case in a row at once (byte x: cell x's, bit c set if corner c is inside), from
// the row's corner rows (rowCorners).
std::uint64_t rowConfigs(const std::uint32_t (&r)[4]);

// The case (bit c: corner c inside) of the cell at block-local position l.
inline int cellConfig(const FillBlock& block, const glm::ivec3& l, Fill corner[8]) {
  int config = 0;
  for (int c = 0; c < 8; ++c) {
    corner[c] = blockFill(block, l.x + (c & 1), l.y + ((c >> 1) & 1), l.z + ((c >> 2) & 1));
    if (double(corner[c]) > kIso) config |= 1 << c;
  }
  return config;
}

// Offset of cube edge e's first corner from the cell: edge e = 4 axis + bu + 2 bv runs along
// `axis` from (bu << u) | (bv << v), u = axis + 1, v = axis + 2 (mod 3). A table, so the hot
// loop does not call into the table generator.
inline constexpr std::array<std::array<int, 3>, 12> kEdgeStartOffset = [] {
  std::array<std::array<int, 3>, 12> t{};
  for (int e = 0; e < 12; ++e) {
    const int axis = e / 4;
    t[std::size_t(e)][std::size_t((axis + 1) % 3)] = e & 1;
    t[std::size_t(e)][std::size_t((axis + 2) % 3)] = (e >> 1) & 1;
  }
  return t;
}();

// The first voxel of cube edge e of a cell (the cell that owns the edge).
inline glm::ivec3 edgeStart(const glm::ivec3& cell, int e) {
  const auto& o = kEdgeStartOffset[std::size_t(e)];
  return cell + glm::ivec3(o[0], o[1], o[2]);
}

}  // namespace osteon::geometry::detail
