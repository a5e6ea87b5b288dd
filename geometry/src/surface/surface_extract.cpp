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
#include "surface_bricks.h"
#include "surface_cases.h"
#include "surface_cells.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace osteon::geometry {

namespace {

using namespace detail;

// Extraction slab by slab (a z layer of cell bricks), each step in parallel over a slab's
// bricks: find the slab's active bricks and count what each adds (edges, triangles, centres),
// which places them in the output; then the slab below's edge vertices and triangles; then, a
// slab further behind, loop centres; all straight into the output arrays, which grow slab by
// slab. A brick's vertices are its edge vertices, then its loop centres; numbering follows
// brick order, so the result does not depend on scheduling.
// The extraction's scratch (per brick state for two slabs, 1.3 KiB per cell brick of a slab;
// offsets for every active brick), kept per thread between calls: sized by the largest
// extraction the thread has run, it spares later calls the page faults of fresh arrays.
struct Scratch {
  std::vector<glm::ivec3> active;
  std::vector<std::uint16_t> brickStates;  // what the parts of two layers of grid bricks hold
  std::vector<ActiveBrickScan::RowBits> brickRowBits;  // and their rows' inside bits
  std::vector<std::int32_t> slotOfBrick;  // cell brick -> its place in out and index (ring), or -1
  std::vector<BrickOut> out;              // per brick state, at ring[s]
  std::vector<EdgeIndex> index;
  std::vector<std::uint32_t> ring;  // brick s's place in out and index
  // Per brick (and one past the last): its first vertex, first loop centre (vertex id), the
  // centre's ordinal among all centres, first triangle, first loop entry.
  std::vector<std::uint32_t> vertexOffset, extraOffset, centreOffset, triOffset, loopOffset;
  Buffer<std::uint32_t> centreEntry;  // without smoothing: where each loop centre's loop starts
  std::array<std::size_t, 4>
      lastTotals{};  // vertices, triangles, loop entries, centres made last time
};

// Marks a loop centre writeBrick placed itself (loopStart's top bit; loop entries stay below).
constexpr std::uint32_t kCentrePlaced = 0x80000000u;

// Works in this thread's scratch, borrowed for its lifetime (contents are overwritten,
// capacity kept).
struct Builder : Scratch {
  const VoxelGrid& grid;
  const SurfaceOptions& options;
  glm::ivec3 dims;
  glm::ivec3 cellBricks;  // cell bricks per axis, including the -1 border layer
  bool shared;
  // Without smoothing nothing slides along its edge afterwards, so vertices are written as
  // positions straight away and the per-vertex edge record (VertexInfo) is never made.
  bool direct;

  static Scratch& threadScratch() {
    static thread_local Scratch scratch;
    return scratch;
  }
  ~Builder() { std::swap(static_cast<Scratch&>(*this), threadScratch()); }
  Builder(const Builder&) = delete;
  Builder& operator=(const Builder&) = delete;

  Builder(const VoxelGrid& g, const SurfaceOptions& o)
      : grid(g),
        options(o),
        dims(g.dims()),
        shared(o.method == SurfaceMethod::CrackFree),
        direct(o.smoothIterations == 0) {
    cellBricks = g.brickDims() + 1;
    std::swap(static_cast<Scratch&>(*this), threadScratch());
    active.clear();
  }

  std::size_t cellBrickIndex(const glm::ivec3& cb) const {  // cb from -1
    return std::size_t(cb.x + 1) +
           std::size_t(cellBricks.x) *
               (std::size_t(cb.y + 1) + std::size_t(cellBricks.y) * std::size_t(cb.z + 1));
  }

  // The rows pass 1 found mixed cells in, in byte order: later passes skip the rest.
  template <typename Fn>
  static void forEachSurfaceRow(const BrickOut& o, Fn&& fn) {
    for (std::uint64_t rows = o.surfaceRows; rows != 0; rows &= rows - 1) {
      const int row = __builtin_ctzll(rows);
      fn(row, row & (kBrickEdge - 1), row >> 3);
    }
  }

  // Pass 1 on brick s (surface_count.cpp).
  void count(std::size_t s, const ActiveBrickScan& scan) {
    countBrick(grid, scan, active[s], shared, out[ring[s]], index[ring[s]]);
  }

  // Pass 2 (crack-free): one vertex per crossed edge, made by the cell that owns it, layer by
  // layer, axis by axis, one 64-bit word of a layer's crossings at a time (bit x + 8 y), its
  // fills read in place. A loop per layer and axis rather than per row and axis: a row has
  // about one crossing per axis, so the predictor cannot foresee where per-row loops end.
  // kDirect: positions straight away (no smoothing to follow), else edge records. Each
  // vertex's id also goes into the brick's edge-id table (ownIds) for its triangles.
  template <bool kDirect>
  void writeEdgeVertices(std::size_t s, VertexInfo* vertices, glm::dvec3* positions,
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

  // Passes 2 and 3 of one brick (crack-free): its edge vertices, whose ids go straight into
  // the brick's edge-id table, then the ids its cells share with the bricks above (numbered
  // in pass 1), then its triangles and loop centres. A case without a long loop writes its
  // triangles from fixed offsets into the table, with no search and no count. Positions of
  // loop centres need vertices of bricks not yet made, so here a centre gets its loop's ids
  // (loopStart: where they start) and placeCentres makes it later.
  template <bool kDirect>
  void writeBrick(std::size_t s, VertexInfo* vertices, glm::dvec3* positions,
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
      const auto* configs = reinterpret_cast<const std::uint8_t*>(o.configs.data() +
                                                                  kBrickEdge * lz);  // byte x + 8 y
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
          if (kDirect && lx < kBrickEdge - 1 && ly < kBrickEdge - 1 && lz < kBrickEdge - 1) {
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
    }
  }

  // Without smoothing: brick s's loop centres at their loops' means, once the bricks above it
  // have made their vertices (those writeBrick placed itself are marked in loopStart).
  void placeCentres(std::size_t s, glm::dvec3* positions, const std::uint32_t* loopVertices,
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
  void gatherFaceIds(std::size_t s, EdgeIds& edgeIds) const {
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
      if (nb.x >= cellBricks.x - 1 || nb.y >= cellBricks.y - 1 || nb.z >= cellBricks.z - 1)
        return -1;
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
  static void rowOfIds(std::uint32_t first, std::uint8_t crossings, std::uint32_t* ids) {
    const std::uint32_t* below = kCrossingsBelow[crossings].data();
#if defined(__SSE2__)
    const __m128i base = _mm_set1_epi32(std::int32_t(first));
    const auto* b = reinterpret_cast<const __m128i*>(below);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(ids), _mm_add_epi32(base, _mm_load_si128(b)));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(ids + 4),
                     _mm_add_epi32(base, _mm_load_si128(b + 1)));
#else
    for (int x = 0; x < kCellBrick; ++x) ids[x] = first + below[x];
#endif
  }

  // The naive baseline: every cube makes its own vertex on each of its crossed edges.
  void writeTrianglesNaive(std::size_t s, Buffer<VertexInfo>& vertices,
                           Buffer<glm::dvec3>& positions, Buffer<std::uint32_t>& loopVertices,
                           Buffer<glm::u32vec3>& triangles) {
    const auto& table = mcTable();
    const glm::ivec3 cb = active[s];
    const BrickOut& o = out[ring[s]];
    std::uint32_t nextTri = triOffset[s];
    std::uint32_t nextExtra = extraOffset[s];
    std::uint32_t nextEntry = loopOffset[s];
    forEachSurfaceRow(o, [&](int row, int ly, int lz) {
      const std::uint64_t configs = o.configs[std::size_t(row)];
      for (std::uint32_t bits = o.mixed[std::size_t(row)]; bits != 0; bits &= bits - 1) {
        const glm::ivec3 l(__builtin_ctz(bits), ly, lz);
        const McCase& mc = table[std::size_t((configs >> (8 * l.x)) & 0xffu)];
        std::uint32_t ids[13];
        for (int loop = 0; loop < mc.loopCount; ++loop) {
          int count = 0;
          for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1];
               ++k) {
            const int e = mc.edges[std::size_t(k)];
            const glm::ivec3 start = edgeStart(l, e);
            const int axis = e / 4;
            const VertexInfo v = edgeVertexInfo(
                grid, cb * kBrickEdge + start, axis, o.source.at(start.x, start.y, start.z),
                o.source.at(start.x + (axis == 0), start.y + (axis == 1), start.z + (axis == 2)));
            if (direct) {
              positions[nextExtra] = positionOf(v);
            } else {
              vertices[nextExtra] = v;
            }
            ids[count++] = nextExtra++;
          }
          if (count == 3) {
            triangles[nextTri++] = {ids[0], ids[1], ids[2]};
          } else if (count == 4) {
            triangles[nextTri++] = {ids[0], ids[1], ids[2]};
            triangles[nextTri++] = {ids[0], ids[2], ids[3]};
          } else {
            // Longer loops fan from their centre, as in the crack-free method.
            if (direct) {
              glm::dvec3 sum(0.0);
              for (int i = 0; i < count; ++i) sum += positions[ids[i]];
              positions[nextExtra] = sum / double(count);
            } else {
              std::copy(ids, ids + count, loopVertices.begin() + nextEntry);
              vertices[nextExtra] = {glm::dvec3(0.0), 3, 0.0, 0.0, nextEntry, std::uint32_t(count),
                                     glm::ivec3(0)};
              nextEntry += std::uint32_t(count);
            }
            const std::uint32_t centre = nextExtra++;
            for (int i = 0; i < count; ++i)
              triangles[nextTri++] = {centre, ids[i], ids[(i + 1) % count]};
          }
        }
      }
    });
  }

  void run(Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
           Buffer<std::uint32_t>& loopVertices, Buffer<glm::u32vec3>& triangles,
           std::vector<SurfaceMesh::BrickRange>& ranges) {
    // With one thread allowed, plain loops: TBB's tasks and partitioner cost a single thread
    // time and buy it nothing (a 64^3 extraction runs 27 loops, three per slab).
    const bool serial =
        std::min<std::size_t>(
            tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
            std::size_t(tbb::this_task_arena::max_concurrency())) <= 1;
    const auto forEachBrickIn = [&](std::size_t first, std::size_t last, auto&& work) {
      if (serial) {
        for (std::size_t s = first; s < last; ++s) work(s);
        return;
      }
      tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 4),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t s = r.begin(); s != r.end(); ++s) work(s);
                        });
    };
    // Slab by slab (a z layer of cell bricks): which cell bricks hold surface and pass 1 on
    // them, their places in the output, then the slab below's vertices, ids and triangles
    // (its cells share edges with this slab, numbered just now), then the loop centres of the
    // slab below that (their loops reach into the slab above them). What each step reads
    // was made a moment before and is still in cache. Numbering follows brick order (a
    // brick's edge vertices, then its loop centres), so it does not depend on scheduling.
    slotOfBrick.assign(
        std::size_t(cellBricks.x) * std::size_t(cellBricks.y) * std::size_t(cellBricks.z), -1);
    vertexOffset.assign(1, 0);
    centreOffset.assign(1, 0);
    triOffset.assign(1, 0);
    loopOffset.assign(1, 0);
    extraOffset.clear();
    // Per brick state for two slabs at a time (pass 1 on one while the brick pass reads the
    // slab below and its own), a half for each: the same few hundred KiB, in cache, all along.
    const std::size_t slabBricks = std::size_t(cellBricks.x) * std::size_t(cellBricks.y);
    out.resize(2 * slabBricks);
    index.resize(2 * slabBricks);
    ring.clear();
    // Outputs grow slab by slab. Room for as much as this thread's last extraction made spares
    // repeated extractions of a changing grid any regrowth; a first one goes by the grid's
    // stored bricks: a smooth surface makes 50-90 vertices per stored brick (the humerus at
    // 0.25-1.2 mm, a voxelized sphere) and about two triangles per vertex, so 96 leave room for
    // it without regrowing (a fresh allocation and a copy); noise makes ~1,000 and regrows.
    const std::size_t vertexGuess = 96 * grid.allocatedBrickCount();
    const std::array<std::size_t, 4> room = {
        std::max(lastTotals[0], vertexGuess), std::max(lastTotals[1], 2 * vertexGuess),
        std::max(lastTotals[2], vertexGuess / 2), std::max(lastTotals[3], vertexGuess / 8)};
    if (direct) {
      positions.reserve(room[0]);
    } else {
      vertices.reserve(room[0]);
    }
    triangles.reserve(room[1]);
    loopVertices.reserve(room[2]);
    if (direct && shared) centreEntry.reserve(room[3]);
    const auto brick = [&](std::size_t s) {
      if (!shared) {
        writeTrianglesNaive(s, vertices, positions, loopVertices, triangles);
      } else if (direct) {
        writeBrick<true>(s, nullptr, positions.data(), loopVertices.data(), centreEntry.data(),
                         triangles.data());
      } else {
        writeBrick<false>(s, vertices.data(), nullptr, loopVertices.data(), nullptr,
                          triangles.data());
      }
    };
    const auto centres = [&](std::size_t s) {
      placeCentres(s, positions.data(), loopVertices.data(), centreEntry.data());
    };
    const bool placeLater = direct && shared;
    ActiveBrickScan scan(grid, brickStates, brickRowBits);
    std::size_t written = 0, placed = 0;  // bricks before these are written, have their centres
    for (int z = -1; z + 1 < cellBricks.z; ++z) {
      const std::size_t first = active.size();
      scan.slab(z, active);
      const std::size_t last = active.size();
      for (std::size_t s = first; s < last; ++s)
        ring.push_back(std::uint32_t(((z + 1) & 1) * slabBricks + (s - first)));
      forEachBrickIn(first, last, [&](std::size_t s) { count(s, scan); });
      for (std::size_t s = first; s < last; ++s) {
        const BrickOut& o = out[ring[s]];
        slotOfBrick[cellBrickIndex(active[s])] = std::int32_t(ring[s]);
        index[ring[s]].firstEdgeVertex = vertexOffset[s];
        extraOffset.push_back(vertexOffset[s] + o.edges);
        vertexOffset.push_back(extraOffset[s] + o.extras);
        centreOffset.push_back(centreOffset[s] + o.extras);
        triOffset.push_back(triOffset[s] + o.triangles);
        loopOffset.push_back(loopOffset[s] + o.loopEntries);
      }
      // Past the room reserved, regrow once for the whole grid, projected from the cell layers
      // done (a volume of noise, some 1,000 vertices per stored brick, shows on its first
      // slabs), rather than by doubling, each step of which is a fresh allocation and a copy.
      const double layersDone =
          std::min(kBrickEdge * (z + 1) + 1, dims.z + 1);  // cell layers -1 .. 8 z + 7
      const auto grow = [&](auto& buffer, std::size_t size) {
        if (size > buffer.capacity()) {
          buffer.reserve(std::size_t(double(size) * double(dims.z + 1) / layersDone * 1.25) + 1024);
        }
        buffer.resize(size);
      };
      if (direct) {
        grow(positions, vertexOffset[last]);
      } else {
        grow(vertices, vertexOffset[last]);
      }
      grow(triangles, triOffset[last]);
      grow(loopVertices, loopOffset[last]);
      if (placeLater) grow(centreEntry, centreOffset[last]);
      forEachBrickIn(written, first, brick);
      if (placeLater) forEachBrickIn(placed, written, centres);
      placed = written;
      written = first;
    }
    const std::size_t n = active.size();
    forEachBrickIn(written, n, brick);
    if (placeLater) {
      forEachBrickIn(placed, written, centres);
      forEachBrickIn(written, n, centres);
    }
    lastTotals = {vertexOffset[n], triOffset[n], loopOffset[n], centreOffset[n]};
    // A mesh far smaller than the last does not keep the last one's room.
    const auto fit = [](auto& buffer) {
      if (buffer.capacity() > 2 * buffer.size() + 4096) buffer.shrink_to_fit();
    };
    fit(positions);
    fit(vertices);
    fit(triangles);
    ranges.reserve(ranges.size() + n);  // one allocation, not a dozen regrowths
    for (std::size_t s = 0; s < n; ++s) {
      if (triOffset[s + 1] > triOffset[s]) {
        ranges.push_back({std::int64_t(cellBrickIndex(active[s])), active[s], triOffset[s],
                          triOffset[s + 1] - triOffset[s]});
      }
    }
  }
};

}  // namespace

void validateSurfaceOptions(const SurfaceOptions& options) {
  if (options.smoothIterations < 0 || options.smoothIterations > 100) {
    throw InputError("--smooth " + std::to_string(options.smoothIterations) +
                     ": passes must be 0..100");
  }
  if (!(options.lambda > 0.0 && options.lambda <= 1.0) ||
      !(options.mu < 0.0 && options.mu >= -1.0)) {
    std::ostringstream s;
    s << "smoothing weights lambda " << options.lambda << ", mu " << options.mu
      << ": need 0 < lambda <= 1 and -1 <= mu < 0";
    throw InputError(s.str());
  }
}

SurfaceMesh extractSurface(const VoxelGrid& grid, const SurfaceOptions& options,
                           SurfaceTimings* timings) {
  validateSurfaceOptions(options);
  SurfaceTimings local;
  const Clock::time_point start = Clock::now();
  Buffer<VertexInfo> vertices;
  Buffer<std::uint32_t> loopVertices;
  Buffer<glm::u32vec3> triangles;
  std::vector<SurfaceMesh::BrickRange> ranges;
  SurfaceMesh mesh;
  bool direct = false;
  {
    Builder builder(grid, options);
    builder.run(vertices, mesh.positionsMm, loopVertices, triangles, ranges);
    direct = builder.direct;
  }
  local.extractMs = msSince(start);

  if (direct) {
    const Clock::time_point phase = Clock::now();
    if (options.computeNormals) areaWeightedNormals(mesh.positionsMm, triangles, mesh.normals);
    local.normalsMs = msSince(phase);
  } else {
    finishSurface(vertices, loopVertices, triangles,
                  {options.smoothIterations, options.lambda, options.taubin, options.mu,
                   options.computeNormals},
                  mesh.positionsMm, mesh.normals, local.otherMs, local.smoothMs, local.normalsMs);
  }
  mesh.triangles = std::move(triangles);
  mesh.brickRanges = std::move(ranges);
  local.totalMs = msSince(start);
  if (timings) *timings = local;
  return mesh;
}

}  // namespace osteon::geometry
