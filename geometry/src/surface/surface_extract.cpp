#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/surface/surface.h"
#include "surface_builder.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
namespace osteon::geometry::detail {

// Pass 2 (crack-free): one vertex per crossed edge, made by the cell that owns it, layer by
// layer, axis by axis, one 64-bit word of a layer's crossings at a time (bit x + 8 y), its
// fills read in place. A loop per layer and axis rather than per row and axis: a row has
// about one crossing per axis, so the predictor cannot foresee where per-row loops end.
// kDirect: positions straight away (no smoothing to follow), else edge records. Each
// vertex's id also goes into the brick's edge-id table (ownIds) for its triangles.
template <bool kDirect>
void Builder::writeEdgeVertices(std::size_t s, VertexInfo* vertices, glm::dvec3* positions,
                                std::uint32_t* ownIds) const {
  const BrickOut& o = out[ring[s]];
  const BlockSource& src = o.source;
  const glm::ivec3 cb = active[s];
  const double vs = grid.voxelSizeMm();
  // Voxel centres as grid.voxelCentreMm makes them (so every extractor agrees to the bit),
  // each axis's once per brick.
  std::array<glm::dvec3, kCellBrick> centre;
  for (int i = 0; i < kCellBrick; ++i)
    centre[std::size_t(i)] = grid.voxelCentreMm(cb * kBrickEdge + glm::ivec3(i));
  const EdgeIndex& own = index[ring[s]];
  std::uint32_t id = own.firstEdgeVertex;
  VertexInfo* info = vertices + id;
  glm::dvec3* position = positions + id;
  for (std::uint32_t layers = o.surfaceLayers(); layers != 0; layers &= layers - 1) {
    const int lz = __builtin_ctz(layers);
    const auto edges = [&](auto axisTag) {
      constexpr int axis = decltype(axisTag)::value;
      std::uint64_t bits;
      std::memcpy(&bits, own.crossings.data() + edgeByte(kBrickEdge * lz, axis), sizeof bits);
      std::uint32_t* layerIds = ownIds + idSlot(0, 0, lz, axis);
      const auto make = [&](int lx, int ly, Fill a, Fill b) {
        layerIds[ly * kSlotsPerRow + lx] = id++;
        const double t = edgeParameter(a, b);
        glm::dvec3 p(centre[std::size_t(lx)].x, centre[std::size_t(ly)].y,
                     centre[std::size_t(lz)].z);
        if constexpr (kDirect) {
          p[axis] += t * vs;
          *position++ = p;
        } else {
          *info++ = {p, axis, t, vs, 0, 0, cb * kBrickEdge + glm::ivec3(lx, ly, lz)};
        }
      };
      if (!src.dense) {  // a block at the grid's border: fills through its bounds
        for (; bits != 0; bits &= bits - 1) {
          const int cell = __builtin_ctzll(bits);
          const int lx = cell & (kBrickEdge - 1), ly = cell >> 3;
          make(lx, ly, src.at(lx, ly, lz),
               src.at(lx + (axis == 0), ly + (axis == 1), lz + (axis == 2)));
        }
        return;
      }
      // Voxel (x, y) of the layer is layer[cell], cell = x + 8 y, in the block's first grid
      // brick. The next along the axis is inner[cell], in the same brick, but for the last
      // voxel along the axis: its next is the first of the brick above, outer[cell - shift].
      const Fill* layer = src.data[0] + kBrickEdge * kBrickEdge * lz;
      const Fill* inner = layer + (axis == 0   ? 1
                                   : axis == 1 ? kBrickEdge
                                               : kBrickEdge * kBrickEdge);
      const Fill* outer = axis == 0   ? src.data[1] + kBrickEdge * kBrickEdge * lz
                          : axis == 1 ? src.data[2] + kBrickEdge * kBrickEdge * lz
                                      : (lz == kBrickEdge - 1 ? src.data[4] : inner);
      constexpr int shift = axis == 0   ? kBrickEdge - 1
                            : axis == 1 ? kBrickEdge * (kBrickEdge - 1)
                                        : 0;
      for (; bits != 0; bits &= bits - 1) {
        const int cell = __builtin_ctzll(bits);
        const int lx = cell & (kBrickEdge - 1), ly = cell >> 3;
        const bool last =
            axis == 0 ? lx == kBrickEdge - 1 : (axis == 1 ? ly == kBrickEdge - 1 : true);
        const Fill* far = last ? outer : inner;  // selects, not branches
        make(lx, ly, layer[cell], far[cell - (last ? shift : 0)]);
      }
    };
    edges(std::integral_constant<int, 0>{});
    edges(std::integral_constant<int, 1>{});
    edges(std::integral_constant<int, 2>{});
  }
}

// One cell whose case has a long loop, loop by loop: a loop of three or four edges as a fan, one
// of five or more around its centre.
template <bool kDirect>
void Builder::writeLoopCell(std::size_t s, const FlatCase& fc, const std::uint32_t* cellIds,
                            bool interior, glm::dvec3* positions, VertexInfo* vertices,
                            std::uint32_t* loopVertices, std::uint32_t* centreStart,
                            glm::u32vec3*& tri, std::uint32_t& nextExtra,
                            std::uint32_t& nextEntry) const {
  // Loop by loop, in the table's order; a loop of five or more edges fans around its
  // centre, which smoothing keeps at the loop's mean.
  const std::uint16_t* slot = fc.slots.data();
  const int loops = fc.loopCount;
  const auto lengths = fc.loopLength;
  for (int loop = 0; loop < loops; slot += lengths[std::size_t(loop)], ++loop) {
    const std::uint32_t k = lengths[std::size_t(loop)];
    if (k < 5) {
      const std::uint32_t a = cellIds[slot[0]];
      for (std::uint32_t i = 1; i + 1 < k; ++i)
        *tri++ = {a, cellIds[slot[i]], cellIds[slot[i + 1]]};
      continue;
    }
    const std::uint32_t centre = nextExtra++;
    const std::uint32_t firstId = cellIds[slot[0]];
    // A cell off the brick's upper faces uses only the brick's own edges, whose vertices
    // were just made: without smoothing its centre is placed now, from their positions
    // while they are in cache, and its loop needs no entries for later.
    if (kDirect && interior) {
      glm::dvec3 sum(0.0);
      std::uint32_t id = firstId;
      for (std::uint32_t i = 0; i < k; ++i) {
        const std::uint32_t nextId = i + 1 < k ? cellIds[slot[i + 1]] : firstId;
        *tri++ = {centre, id, nextId};
        sum += positions[id];
        id = nextId;
      }
      positions[centre] = sum / double(k);
      centreStart[centre - extraOffset[s]] = nextEntry | kCentrePlaced;
      nextEntry += k;
      continue;
    }
    std::uint32_t id = firstId;
    for (std::uint32_t i = 0; i < k; ++i) {
      const std::uint32_t nextId = i + 1 < k ? cellIds[slot[i + 1]] : firstId;
      *tri++ = {centre, id, nextId};
      loopVertices[nextEntry + i] = id;
      id = nextId;
    }
    if constexpr (kDirect) {
      centreStart[centre - extraOffset[s]] = nextEntry;
    } else {
      vertices[centre] = {glm::dvec3(0.0), 3, 0.0, 0.0, nextEntry, k, glm::ivec3(0)};
    }
    nextEntry += k;
  }
}

// Passes 2 and 3 of one brick (crack-free): its edge vertices, whose ids go straight into
// the brick's edge-id table, then the ids its cells share with the bricks above (numbered
// in pass 1), then its triangles and loop centres. A case without a long loop writes its
// triangles from fixed offsets into the table, with no search and no count. Positions of
// loop centres need vertices of bricks not yet made, so here a centre gets its loop's ids
// (loopStart: where they start) and placeCentres makes it later.
template <bool kDirect>
void Builder::writeBrick(std::size_t s, VertexInfo* vertices, glm::dvec3* positions,
                         std::uint32_t* loopVertices, std::uint32_t* loopStart,
                         glm::u32vec3* triangles) const {
  const BrickOut& o = out[ring[s]];
  if (o.surfaceRows == 0) return;  // e.g. a border brick whose one layer of cells is all outside
  const auto& flat = flatCases();
  EdgeIds edgeIds;  // only crossed edges' slots are read, and each of those is written first
  writeEdgeVertices<kDirect>(s, vertices, positions, edgeIds.data());
  gatherFaceIds(s, edgeIds);
  // Raw pointers, and counts read once: the writes go through types that may alias the
  // tables (bytes), so the compiler would otherwise reload them after every store.
  glm::u32vec3* tri = triangles + triOffset[s];
  glm::u32vec3* const triEnd =
      triangles + triOffset[s + 1];  // the brick's range: never written past
  std::uint32_t nextExtra = extraOffset[s];
  std::uint32_t nextEntry = loopOffset[s];
  std::uint32_t* centreStart =
      kDirect ? loopStart + centreOffset[s] : nullptr;  // by centre - extraOffset[s]
  // Cell by cell, a layer's mixed cells as one 64-bit word (bit x + 8 y), as in pass 2.
  for (std::uint32_t layers = o.surfaceLayers(); layers != 0; layers &= layers - 1) {
    const int lz = __builtin_ctz(layers);
    std::uint64_t bits;
    std::memcpy(&bits, o.mixed.data() + kBrickEdge * lz, sizeof bits);
    const auto* configs =
        reinterpret_cast<const std::uint8_t*>(o.configs.data() + kBrickEdge * lz);  // byte x + 8 y
    const std::uint32_t* layerIds = edgeIds.data() + idSlot(0, 0, lz, 0);
    for (; bits != 0; bits &= bits - 1) {
      const int cell = __builtin_ctzll(bits);
      const int lx = cell & (kBrickEdge - 1), ly = cell >> 3;
      const FlatCase& fc = flat[configs[cell]];
      const std::uint32_t* cellIds = layerIds + ly * kSlotsPerRow + lx;
      if (fc.longLoops == 0) {
        const std::uint16_t* corner = fc.slots.data();
        const int n = fc.triangleCount;
        // With room for four triangles in the brick's range (all but its last cells), two
        // are written whatever the count (a case's unused slots repeat its first triangle,
        // and the next cell writes over them) and two more for three or four: the common
        // counts, one and two, take no branch on the count, whose loop exit the predictor
        // cannot foresee cell by cell.
        if (tri + 4 <= triEnd) {
          tri[0] = {cellIds[corner[0]], cellIds[corner[1]], cellIds[corner[2]]};
          tri[1] = {cellIds[corner[3]], cellIds[corner[4]], cellIds[corner[5]]};
          if (n > 2) {
            tri[2] = {cellIds[corner[6]], cellIds[corner[7]], cellIds[corner[8]]};
            tri[3] = {cellIds[corner[9]], cellIds[corner[10]], cellIds[corner[11]]};
          }
        } else {
          for (int t = 0; t < n; ++t, corner += 3)
            tri[t] = {cellIds[corner[0]], cellIds[corner[1]], cellIds[corner[2]]};
        }
        tri += n;
        continue;
      }
      writeLoopCell<kDirect>(
          s, fc, cellIds, lx < kBrickEdge - 1 && ly < kBrickEdge - 1 && lz < kBrickEdge - 1,
          positions, vertices, loopVertices, centreStart, tri, nextExtra, nextEntry);
    }
  }
}

// Without smoothing: brick s's loop centres at their loops' means, once the bricks above it
// have made their vertices (those writeBrick placed itself are marked in loopStart).
void Builder::placeCentres(std::size_t s, glm::dvec3* positions, const std::uint32_t* loopVertices,
                           const std::uint32_t* loopStart) const {
  const std::uint32_t* starts = loopStart + centreOffset[s];
  const std::uint32_t count = centreOffset[s + 1] - centreOffset[s];
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::uint32_t first = starts[k];
    if ((first & kCentrePlaced) != 0) continue;
    const std::uint32_t last = k + 1 < count ? starts[k + 1] & ~kCentrePlaced : loopOffset[s + 1];
    glm::dvec3 sum(0.0);
    for (std::uint32_t e = first; e < last; ++e) sum += positions[loopVertices[e]];
    positions[extraOffset[s] + k] = sum / double(last - first);
  }
}

// The ids of the crossed edges brick s's cells share with the bricks above (octant d: +x if
// d & 1, +y if d & 2, +z if d & 4), on its upper faces, into their table slots, from each
// owner's pass 1 counts (its first id plus the crossings before the edge's row). An edge
// there lies in a row of the owner's cells with a mixed cell, which pass 1 recorded; only
// the owner's rows next to our cells with surface on the face are read. A row's eight slots
// are written whether crossed or not (no branch per edge): only crossed edges' slots are
// ever read.
void Builder::gatherFaceIds(std::size_t s, EdgeIds& edgeIds) const {
  const glm::ivec3 cb = active[s];
  // Rows (bit y + 8 z) of each owner that our cells use: a cell (7, y, z) uses the +x
  // brick's edges in its rows (y, z), (y + 1, z), (y, z + 1); (x, 7, z) the +y brick's in
  // (0, z), (0, z + 1); (x, y, 7) the +z brick's in (y, 0), (y + 1, 0); and so on along the
  // lines where two faces meet.
  constexpr std::uint64_t kRowsY0 = 0x0101010101010101ull;  // y = 0
  const BrickOut& o = out[ring[s]];
  const std::uint64_t lastX = o.lastCellRows;
  const std::uint64_t lastY = (o.surfaceRows >> 7) & kRowsY0;  // our rows (7, z), as (0, z)
  const std::uint64_t lastZ = o.surfaceRows >> 56;             // our rows (y, 7), as (y, 0)
  const std::uint64_t rowsOf[7] = {0,
                                   lastX | ((lastX << 1) & ~kRowsY0) | (lastX << 8),
                                   lastY | (lastY << 8),
                                   (lastX >> 7) & kRowsY0,
                                   lastZ | ((lastZ << 1) & 0xffu),
                                   lastX >> 56,
                                   o.surfaceRows >> 63};
  const auto owner = [&](int d) -> std::int32_t {
    const glm::ivec3 nb = cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1);
    if (nb.x >= cellBricks.x - 1 || nb.y >= cellBricks.y - 1 || nb.z >= cellBricks.z - 1) return -1;
    return slotOfBrick[cellBrickIndex(nb)];
  };
  // Along which axes the owner's edges lie on our faces, and whether all eight x of a row
  // (those above along y and z) or only x = 0 (those along +x). No cell uses an edge of the
  // brick diagonally above (d = 7).
  const auto face = [&](auto dTag, auto axesTag) {
    constexpr int d = decltype(dTag)::value;
    constexpr int axes = decltype(axesTag)::value;
    const std::uint64_t rowsTaken = rowsOf[d];
    if (rowsTaken == 0) return;
    const std::int32_t slot = owner(d);
    if (slot < 0) return;
    const EdgeIndex& from = index[std::size_t(slot)];
    std::uint32_t* shifted =
        edgeIds.data() +
        idSlot(kBrickEdge * (d & 1), kBrickEdge * ((d >> 1) & 1), kBrickEdge * ((d >> 2) & 1), 0);
    for (std::uint64_t rows = out[std::size_t(slot)].surfaceRows & rowsTaken; rows != 0;
         rows &= rows - 1) {
      const int row = __builtin_ctzll(rows);
      std::uint32_t* rowIds = shifted + idSlot(0, row & (kBrickEdge - 1), row >> 3, 0);
      const auto axis = [&](auto axisTag) {
        constexpr int a = decltype(axisTag)::value;
        if constexpr (((axes >> a) & 1) != 0) {
          const std::size_t byte = edgeByte(row, a);
          const std::uint32_t first = from.firstEdgeVertex + from.crossingsBefore[byte];
          if constexpr ((d & 1) == 0) {
            rowOfIds(first, from.crossings[byte], rowIds + a * kBlock);
          } else {
            rowIds[a * kBlock] = first;
          }
        }
      };
      axis(std::integral_constant<int, 0>{});
      axis(std::integral_constant<int, 1>{});
      axis(std::integral_constant<int, 2>{});
    }
  };
  face(std::integral_constant<int, 1>{}, std::integral_constant<int, 6>{});
  face(std::integral_constant<int, 2>{}, std::integral_constant<int, 5>{});
  face(std::integral_constant<int, 3>{}, std::integral_constant<int, 4>{});
  face(std::integral_constant<int, 4>{}, std::integral_constant<int, 3>{});
  face(std::integral_constant<int, 5>{}, std::integral_constant<int, 2>{});
  face(std::integral_constant<int, 6>{}, std::integral_constant<int, 1>{});
}

// ids[x] = first + the crossings below x in a row's byte, for x = 0..7.
void Builder::rowOfIds(std::uint32_t first, std::uint8_t crossings, std::uint32_t* ids) {
  const std::uint32_t* below = kCrossingsBelow[crossings].data();
#if defined(__SSE2__)
  const __m128i base = _mm_set1_epi32(std::int32_t(first));
  const auto* b = reinterpret_cast<const __m128i*>(below);
  _mm_storeu_si128(reinterpret_cast<__m128i*>(ids), _mm_add_epi32(base, _mm_load_si128(b)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(ids + 4), _mm_add_epi32(base, _mm_load_si128(b + 1)));
#else
  for (int x = 0; x < kCellBrick; ++x) ids[x] = first + below[x];
#endif
}

template void Builder::writeBrick<true>(std::size_t, VertexInfo*, glm::dvec3*, std::uint32_t*,
                                        std::uint32_t*, glm::u32vec3*) const;
template void Builder::writeBrick<false>(std::size_t, VertexInfo*, glm::dvec3*, std::uint32_t*,
                                         std::uint32_t*, glm::u32vec3*) const;

}  // namespace osteon::geometry::detail
