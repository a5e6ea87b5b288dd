#include "osteon/geometry/surface.h"

#include "surface_cells.h"
#include "osteon/geometry/error.h"

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

namespace osteon::geometry {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

using namespace detail;
constexpr int kB = kCellBrick;
// fill > this <=> fill > kIso (fills are integers, kIso sits halfway between two).
constexpr Fill kInsideAbove = Fill(kFillHalf - 1);

// Per active cell brick: what it adds to the surface. Vertex references inside a brick are
// global edge-vertex ids, or (with kLocal set) ids into the brick's own extra vertices (loop
// centres, and every vertex of the naive method), renumbered once all bricks are done.
constexpr std::uint32_t kLocal = 0x80000000u;

// Inside bits of a block, one 9-bit word per (y, z) row (bit x: voxel x is inside), so whole
// rows of cells with no crossing are skipped with a few word operations.
using RowMasks = std::array<std::uint16_t, kBlock * kBlock>;

void insideRows(const FillBlock& block, RowMasks& rows) {
  for (int r = 0; r < kBlock * kBlock; ++r) {
    std::uint16_t m = 0;
    const Fill* f = block.data() + r * kBlock;
    for (int x = 0; x < kBlock; ++x) m = std::uint16_t(m | ((f[x] > kInsideAbove ? 1u : 0u) << x));
    rows[std::size_t(r)] = m;
  }
}

// The cells of a row range whose x lies in [xLo, xHi) (block-local), as a bit mask.
inline std::uint32_t xRange(int xLo, int xHi) {
  return xHi <= xLo ? 0u : ((1u << xHi) - 1u) & ~((1u << xLo) - 1u);
}

struct BrickOut {
  // Left uninitialised: every brick fills its arrays before reading them, and zeroing some
  // 8 KiB per active brick up front was a tenth of the extraction time.
  BrickOut() {}  // NOLINT: deliberately not = default (that would zero the arrays)
  FillBlock block;                        // the voxels its cells read (loaded once)
  RowMasks rows;                          // inside bits of block
  std::vector<VertexInfo> edgeVertices;   // crack-free: owned edge crossings
  std::vector<VertexInfo> extraVertices;  // loop centres; naive: all
  std::vector<std::uint32_t> loopVertices;
  std::vector<glm::u32vec3> triangles;
  std::array<std::uint32_t, 3 * kB * kB * kB> edgeVertex;  // owned edge -> local edge vertex
};

struct Builder {
  const VoxelGrid& grid;
  const SurfaceOptions& options;
  glm::ivec3 dims;
  glm::ivec3 cellBricks;  // cell bricks per axis, including the -1 border layer
  double vs;
  std::vector<glm::ivec3> active;
  std::vector<std::int32_t> slotOfBrick;  // cell brick -> index in active, or -1
  std::vector<BrickOut> out;
  std::vector<std::uint32_t> edgeOffset;  // first global id of each brick's edge vertices

  Builder(const VoxelGrid& g, const SurfaceOptions& o)
      : grid(g), options(o), dims(g.dims()), vs(g.voxelSizeMm()) {
    cellBricks = g.brickDims() + 1;
  }

  std::size_t cellBrickIndex(const glm::ivec3& cb) const {  // cb from -1
    return std::size_t(cb.x + 1) +
           std::size_t(cellBricks.x) * (std::size_t(cb.y + 1) + std::size_t(cellBricks.y) * std::size_t(cb.z + 1));
  }

  static void emitLoop(BrickOut& o, const std::uint32_t* ids, int count) {
    if (count == 3) {
      o.triangles.push_back({ids[0], ids[1], ids[2]});
      return;
    }
    if (count == 4) {
      o.triangles.push_back({ids[0], ids[1], ids[2]});
      o.triangles.push_back({ids[0], ids[2], ids[3]});
      return;
    }
    // Longer loops fan from their centre, which smoothing keeps at the loop's average.
    const auto first = std::uint32_t(o.loopVertices.size());
    o.loopVertices.insert(o.loopVertices.end(), ids, ids + count);
    o.extraVertices.push_back({glm::dvec3(0.0), 3, 0.0, 0.0, first, std::uint32_t(count), glm::ivec3(0)});
    const std::uint32_t centre = kLocal | std::uint32_t(o.extraVertices.size() - 1);
    for (int i = 0; i < count; ++i) o.triangles.push_back({centre, ids[i], ids[(i + 1) % count]});
  }

  // Phase 1 (crack-free): one vertex per crossed edge, made by the cell that owns the edge
  // (the cell at the edge's first voxel), numbered within its brick.
  void makeEdgeVertices(std::size_t s) {
    const glm::ivec3 cb = active[s];
    BrickOut& o = out[s];
    o.edgeVertex.fill(kNoVertex);
    loadBlock(grid, cb, o.block);
    const FillBlock& block = o.block;
    o.edgeVertices.reserve(96);
    insideRows(block, o.rows);
    glm::ivec3 lo, hi;
    cellRange(grid, cb, lo, hi);
    const glm::ivec3 l0 = lo - cb * kB;
    const glm::ivec3 l1 = hi - cb * kB;
    const std::uint32_t cells = xRange(l0.x, l1.x);
    for (int lz = l0.z; lz < l1.z; ++lz)
      for (int ly = l0.y; ly < l1.y; ++ly) {
        const std::uint32_t r = o.rows[std::size_t(ly + kBlock * lz)];
        // Crossed edges along x, y and z, by cell x, as bits.
        const std::uint32_t crossing[3] = {
            (r ^ (r >> 1)) & cells,
            (r ^ o.rows[std::size_t(ly + 1 + kBlock * lz)]) & cells,
            (r ^ o.rows[std::size_t(ly + kBlock * (lz + 1))]) & cells};
        constexpr int kStep[3] = {1, kBlock, kBlock * kBlock};
        for (int axis = 0; axis < 3; ++axis) {
          for (std::uint32_t bits = crossing[axis]; bits != 0; bits &= bits - 1) {
            const int lx = __builtin_ctz(bits);
            const int i = lx + kBlock * (ly + kBlock * lz);
            o.edgeVertex[std::size_t(3 * (lx + kB * (ly + kB * lz)) + axis)] =
                std::uint32_t(o.edgeVertices.size());
            o.edgeVertices.push_back(edgeVertexInfo(grid, cb * kB + glm::ivec3(lx, ly, lz), axis,
                                                    block[std::size_t(i)],
                                                    block[std::size_t(i + kStep[axis])]));
          }
        }
      }
  }

  // Phase 2: triangles of one brick's cells. The hot loop: corner states as bits of the
  // block, and each cube edge's vertex read from the owning brick (this one, or one of the
  // seven above it for cells on its upper faces) without any search.
  void makeTriangles(std::size_t s) {
    const auto& table = detail::mcTable();
    const bool shared = options.method == SurfaceMethod::CrackFree;
    const glm::ivec3 cb = active[s];
    BrickOut& o = out[s];
    if (!shared) loadBlock(grid, cb, o.block);  // crack-free: loaded by makeEdgeVertices
    const FillBlock& block = o.block;
    o.triangles.reserve(192);
    if (!shared) insideRows(block, o.rows);
    const BrickOut* owners[8] = {};
    std::uint32_t ownerOffset[8] = {};
    if (shared) {
      for (int d = 0; d < 8; ++d) {
        const glm::ivec3 nb = cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1);
        if (nb.x >= cellBricks.x - 1 || nb.y >= cellBricks.y - 1 || nb.z >= cellBricks.z - 1) continue;
        const std::int32_t slot = slotOfBrick[cellBrickIndex(nb)];
        if (slot < 0) continue;
        owners[d] = &out[std::size_t(slot)];
        ownerOffset[d] = edgeOffset[std::size_t(slot)];
      }
    }
    static const std::array<int, 8> cornerStep = [] {
      std::array<int, 8> steps{};
      for (int c = 0; c < 8; ++c) steps[std::size_t(c)] = (c & 1) + kBlock * ((c >> 1) & 1) + kBlock * kBlock * ((c >> 2) & 1);
      return steps;
    }();
    glm::ivec3 lo, hi;
    cellRange(grid, cb, lo, hi);
    const glm::ivec3 l0 = lo - cb * kB;
    const glm::ivec3 l1 = hi - cb * kB;
    const std::uint32_t cells = xRange(l0.x, l1.x);
    for (int lz = l0.z; lz < l1.z; ++lz)
      for (int ly = l0.y; ly < l1.y; ++ly) {
        // The four rows of corners of this row of cells; skip it when none differ.
        const std::uint32_t r0 = o.rows[std::size_t(ly + kBlock * lz)];
        const std::uint32_t r1 = o.rows[std::size_t(ly + 1 + kBlock * lz)];
        const std::uint32_t r2 = o.rows[std::size_t(ly + kBlock * (lz + 1))];
        const std::uint32_t r3 = o.rows[std::size_t(ly + 1 + kBlock * (lz + 1))];
        const std::uint32_t any = r0 | r1 | r2 | r3;
        const std::uint32_t all = r0 & r1 & r2 & r3;
        // A cell is mixed when its corners (bits x, x + 1 of the four rows) are not all equal.
        const std::uint32_t mixed = ((any | (any >> 1)) & ~(all & (all >> 1))) & cells;
        for (std::uint32_t bits = mixed; bits != 0; bits &= bits - 1) {
          const int lx = __builtin_ctz(bits);
          const glm::ivec3 l(lx, ly, lz);
          const int base = lx + kBlock * (ly + kBlock * lz);
          const int config = int(((r0 >> lx) & 3u) | (((r1 >> lx) & 3u) << 2) |
                                 (((r2 >> lx) & 3u) << 4) | (((r3 >> lx) & 3u) << 6));
          if (config == 0 || config == 255) continue;
          const detail::McCase& mc = table[std::size_t(config)];
          std::uint32_t ids[13];
          for (int loop = 0; loop < mc.loopCount; ++loop) {
            int count = 0;
            for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1]; ++k) {
              const int e = mc.edges[std::size_t(k)];
              const glm::ivec3 start = edgeStart(l, e);
              if (shared) {
                const int d = (start.x >> 3) | ((start.y >> 3) << 1) | ((start.z >> 3) << 2);
                const glm::ivec3 local = start & (kB - 1);
                ids[count++] = ownerOffset[d] + owners[d]->edgeVertex[std::size_t(
                                   3 * (local.x + kB * (local.y + kB * local.z)) + e / 4)];
                continue;
              }
              // Naive: every cube makes its own vertex on each of its crossed edges.
              const auto corners = edgeCorners(e);
              o.extraVertices.push_back(edgeVertexInfo(grid, cb * kB + start, e / 4,
                                                       block[std::size_t(base + cornerStep[corners[0]])],
                                                       block[std::size_t(base + cornerStep[corners[1]])]));
              ids[count++] = kLocal | std::uint32_t(o.extraVertices.size() - 1);
            }
            emitLoop(o, ids, count);
          }
        }
      }
  }

  void run(std::vector<VertexInfo>& vertices, std::vector<std::uint32_t>& loopVertices,
           std::vector<glm::u32vec3>& triangles, std::vector<SurfaceMesh::BrickRange>& ranges) {
    for (int bz = -1; bz < cellBricks.z - 1; ++bz)
      for (int by = -1; by < cellBricks.y - 1; ++by)
        for (int bx = -1; bx < cellBricks.x - 1; ++bx) {
          if (cellBrickActive(grid, {bx, by, bz})) active.push_back({bx, by, bz});
        }
    slotOfBrick.assign(std::size_t(cellBricks.x) * std::size_t(cellBricks.y) * std::size_t(cellBricks.z), -1);
    for (std::size_t s = 0; s < active.size(); ++s) slotOfBrick[cellBrickIndex(active[s])] = std::int32_t(s);
    out.resize(active.size());
    const bool shared = options.method == SurfaceMethod::CrackFree;

    // Bricks are independent within a phase; each writes only its own BrickOut.
    const auto forEachBrick = [&](auto&& work) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, active.size(), 4),
                        [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t s = r.begin(); s != r.end(); ++s) work(s);
      });
    };
    edgeOffset.assign(active.size() + 1, 0);
    if (shared) {
      forEachBrick([&](std::size_t s) { makeEdgeVertices(s); });
      for (std::size_t s = 0; s < active.size(); ++s) {
        edgeOffset[s + 1] = edgeOffset[s] + std::uint32_t(out[s].edgeVertices.size());
      }
    }
    forEachBrick([&](std::size_t s) { makeTriangles(s); });

    // Number everything in brick order: deterministic, whatever the scheduling.
    std::vector<std::uint32_t> extraOffset(active.size() + 1, edgeOffset.back());
    std::vector<std::uint32_t> triOffset(active.size() + 1, 0), loopOffset(active.size() + 1, 0);
    for (std::size_t s = 0; s < active.size(); ++s) {
      extraOffset[s + 1] = extraOffset[s] + std::uint32_t(out[s].extraVertices.size());
      triOffset[s + 1] = triOffset[s] + std::uint32_t(out[s].triangles.size());
      loopOffset[s + 1] = loopOffset[s] + std::uint32_t(out[s].loopVertices.size());
    }
    vertices.resize(extraOffset.back());
    triangles.resize(triOffset.back());
    loopVertices.resize(loopOffset.back());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, active.size(), 8),
                      [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t s = r.begin(); s != r.end(); ++s) {
        BrickOut& o = out[s];
        const auto resolve = [&](std::uint32_t id) {
          return (id & kLocal) ? extraOffset[s] + (id & ~kLocal) : id;
        };
        std::copy(o.edgeVertices.begin(), o.edgeVertices.end(), vertices.begin() + edgeOffset[s]);
        for (std::size_t k = 0; k < o.extraVertices.size(); ++k) {
          VertexInfo v = o.extraVertices[k];
          if (v.axis == 3) v.loopFirst += loopOffset[s];
          vertices[extraOffset[s] + k] = v;
        }
        for (std::size_t k = 0; k < o.loopVertices.size(); ++k) {
          loopVertices[loopOffset[s] + k] = resolve(o.loopVertices[k]);
        }
        for (std::size_t k = 0; k < o.triangles.size(); ++k) {
          const glm::u32vec3 t = o.triangles[k];
          triangles[triOffset[s] + k] = {resolve(t.x), resolve(t.y), resolve(t.z)};
        }
      }
    });
    for (std::size_t s = 0; s < active.size(); ++s) {
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
    throw InputError("--smooth " + std::to_string(options.smoothIterations) + ": passes must be 0..100");
  }
  if (!(options.lambda > 0.0 && options.lambda <= 1.0) || !(options.mu < 0.0 && options.mu >= -1.0)) {
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
  std::vector<VertexInfo> vertices;
  std::vector<std::uint32_t> loopVertices;
  std::vector<glm::u32vec3> triangles;
  std::vector<SurfaceMesh::BrickRange> ranges;
  {
    Builder builder(grid, options);
    builder.run(vertices, loopVertices, triangles, ranges);
  }
  local.extractMs = msSince(start);

  SurfaceMesh mesh;
  finishSurface(vertices, loopVertices, triangles,
                {options.smoothIterations, options.lambda, options.taubin, options.mu, options.computeNormals},
                mesh.positionsMm, mesh.normals, local.otherMs, local.smoothMs, local.normalsMs);
  mesh.triangles = std::move(triangles);
  mesh.brickRanges = std::move(ranges);
  local.totalMs = msSince(start);
  if (timings) *timings = local;
  return mesh;
}

}  // namespace osteon::geometry
