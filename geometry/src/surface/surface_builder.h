// The crack-free extractor's builder (surface_extract.cpp: the per-brick passes;
// surface_extract_run.cpp: the slab-by-slab driver and the naive baseline).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/geometric.hpp>

#include "osteon/geometry/surface/surface.h"
#include "surface_bricks.h"
#include "surface_cases.h"
#include "surface_cells.h"

namespace osteon::geometry::detail {
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

  // Pass 2 (crack-free) of brick s: its edge vertices (surface_extract.cpp).
  template <bool kDirect>
  void writeEdgeVertices(std::size_t s, VertexInfo* vertices, glm::dvec3* positions,
                         std::uint32_t* ownIds) const;
  // Passes 2 and 3 of brick s (crack-free): vertices, shared ids, triangles, loop centres.
  template <bool kDirect>
  void writeBrick(std::size_t s, VertexInfo* vertices, glm::dvec3* positions,
                  std::uint32_t* loopVertices, std::uint32_t* loopStart,
                  glm::u32vec3* triangles) const;
  // One cell whose case has a loop of five or more edges: its triangles and loop centres.
  template <bool kDirect>
  void writeLoopCell(std::size_t s, const FlatCase& fc, const std::uint32_t* cellIds, bool interior,
                     glm::dvec3* positions, VertexInfo* vertices, std::uint32_t* loopVertices,
                     std::uint32_t* centreStart, glm::u32vec3*& tri, std::uint32_t& nextExtra,
                     std::uint32_t& nextEntry) const;
  // Without smoothing: brick s's loop centres, once the bricks above it are written.
  void placeCentres(std::size_t s, glm::dvec3* positions, const std::uint32_t* loopVertices,
                    const std::uint32_t* loopStart) const;
  // The ids of the crossed edges brick s's cells share with the bricks above.
  void gatherFaceIds(std::size_t s, EdgeIds& edgeIds) const;
  static void rowOfIds(std::uint32_t first, std::uint8_t crossings, std::uint32_t* ids);
  // The naive baseline (surface_extract_run.cpp).
  void writeTrianglesNaive(std::size_t s, Buffer<VertexInfo>& vertices,
                           Buffer<glm::dvec3>& positions, Buffer<std::uint32_t>& loopVertices,
                           Buffer<glm::u32vec3>& triangles);
  // The whole extraction, slab by slab (surface_extract_run.cpp).
  void run(Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
           Buffer<std::uint32_t>& loopVertices, Buffer<glm::u32vec3>& triangles,
           std::vector<SurfaceMesh::BrickRange>& ranges);
  std::size_t prepare(Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
                      Buffer<std::uint32_t>& loopVertices, Buffer<glm::u32vec3>& triangles);
  void finish(std::size_t n, Buffer<VertexInfo>& vertices, Buffer<glm::dvec3>& positions,
              Buffer<glm::u32vec3>& triangles, std::vector<SurfaceMesh::BrickRange>& ranges);
};

}  // namespace osteon::geometry::detail
