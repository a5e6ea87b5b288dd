// The incremental surface updater's state (surface_updater.cpp: updates, the mesh and its
// changes; surface_updater_build.cpp: the first, whole extraction, in parallel).
#pragma once

#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "osteon/core/constants.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "surface_cells.h"
#include "surface_updater_store.h"

namespace osteon::geometry {

namespace updater_detail {

using namespace detail;

inline constexpr int kCells = kBrickEdge * kBrickEdge * kBrickEdge;

inline int cellIndex(const glm::ivec3& l) {
  return l.x + kBrickEdge * (l.y + kBrickEdge * l.z);
}

// Cell ci of a cell brick, its inverse: its coordinates in the brick.
inline glm::ivec3 cellInBrick(int ci) {
  return {ci % kBrickEdge, (ci / kBrickEdge) % kBrickEdge, ci / (kBrickEdge * kBrickEdge)};
}

// True for a grid cell g within the grid's cells [lo, hi) (cellRange).
inline bool cellInRange(const glm::ivec3& g, const glm::ivec3& lo, const glm::ivec3& hi) {
  return glm::all(glm::greaterThanEqual(g, lo)) && glm::all(glm::lessThan(g, hi));
}

}  // namespace updater_detail

using namespace updater_detail;

// A cell's loop of edge vertices as triangles: one for 3 vertices, two for 4, and for more a
// fan from `centre` (the loop's centre vertex). Returns the triangles it appended.
inline int appendLoopTriangles(std::vector<glm::u32vec3>& out, const std::uint32_t* ids, int count,
                               std::uint32_t centre) {
  if (count == 3) {
    out.push_back({ids[0], ids[1], ids[2]});
    return 1;
  }
  if (count == 4) {
    out.push_back({ids[0], ids[1], ids[2]});
    out.push_back({ids[0], ids[2], ids[3]});
    return 2;
  }
  for (int i = 0; i < count; ++i) out.push_back({centre, ids[i], ids[(i + 1) % count]});
  return count;
}

struct SurfaceUpdater::Impl {
  // Made by std::make_unique<CellBrick>() (value-initialised: all zero) where it must start
  // empty; the first extraction makes it with `new CellBrick` and writes every field itself,
  // which spares zeroing 1.3 KB per brick.
  struct CellBrick {
    FillBlock fills;                                 // the voxels read at the last extraction
    std::array<std::uint64_t, kCells / 64> changed;  // bit per cell: it reads a changed voxel
    bool fillsValid;                                 // owned and triangles follow `fills`
    OwnedEdges owned;                                // owned edge -> vertex slot
    std::vector<glm::u32vec3> triangles;             // grouped by cell, cells in order
    // Triangles of cell i: [begin[i], begin[i+1]); a cell has at most 12, a brick 6,144.
    std::array<std::uint16_t, kCells + 1> cellBegin;
    bool isChanged(int ci) const { return (changed[std::size_t(ci >> 6)] >> (ci & 63)) & 1; }
    void setChanged(int ci) { changed[std::size_t(ci >> 6)] |= std::uint64_t(1) << (ci & 63); }
    std::size_t memoryBytes() const {
      return sizeof(*this) - sizeof(owned) + owned.memoryBytes() +
             triangles.capacity() * sizeof(glm::u32vec3);
    }
  };

  const VoxelGrid* grid;
  SurfaceOptions options;
  glm::ivec3 cellBricks;
  double vs;
  std::vector<std::unique_ptr<CellBrick>> bricks;  // dense over cell bricks (from -1)

  // Vertex slots: stable while the vertex lives; freed slots are reused.
  PagedArray<SlotInfo> info;
  PagedArray<glm::dvec3> position;  // smoothed
  PagedArray<glm::dvec3> normal;
  PagedArray<std::uint8_t> alive;
  std::vector<std::uint32_t> freeSlots;
  std::vector<std::uint32_t> pendingFree;
  // Loop centres' loops, kLoopMax vertices per block; freed blocks are reused.
  static constexpr int kLoopMax = 12;
  PagedArray<std::array<std::uint32_t, kLoopMax>> loops;
  std::vector<std::uint32_t> freeLoops;

  // Changes since the last takeChanges(): per slot and per cell brick a flag, and their lists.
  bool everything = true;
  PagedArray<std::uint8_t> slotChanged;
  std::vector<std::uint8_t> brickChanged;
  std::vector<std::uint32_t> changedSlots;
  std::vector<std::uint32_t> changedBricks;
  void noteSlot(std::uint32_t s) {
    if (everything) return;
    if (slotChanged.size() <= s) slotChanged.resize(std::size_t(s) + 1, 0);
    if (!slotChanged[s]) slotChanged[s] = 1, changedSlots.push_back(s);
  }
  void noteBrick(std::size_t b) {
    if (everything) return;
    if (brickChanged.size() < bricks.size()) brickChanged.resize(bricks.size(), 0);
    if (!brickChanged[b]) brickChanged[b] = 1, changedBricks.push_back(std::uint32_t(b));
  }

  // Scratch for updates (kept to avoid reallocating).
  PagedArray<std::uint32_t> mark;  // per slot: epoch of the last visit
  std::uint32_t epoch = 0;

  std::size_t brickIndex(const glm::ivec3& cb) const {
    return std::size_t(cb.x + 1) +
           std::size_t(cellBricks.x) *
               (std::size_t(cb.y + 1) + std::size_t(cellBricks.y) * std::size_t(cb.z + 1));
  }
  bool validBrick(const glm::ivec3& cb) const {
    return cb.x >= -1 && cb.y >= -1 && cb.z >= -1 && cb.x < cellBricks.x - 1 &&
           cb.y < cellBricks.y - 1 && cb.z < cellBricks.z - 1;
  }
  static glm::ivec3 brickOfCell(const glm::ivec3& c) {
    return {floorDiv(c.x, kBrickEdge), floorDiv(c.y, kBrickEdge), floorDiv(c.z, kBrickEdge)};
  }

  // An edge vertex's position before smoothing: what the full extractor computes (positionOf
  // of edgeVertexInfo), from the grid.
  glm::dvec3 edgePosition(const SlotInfo& v) const {
    glm::dvec3 p = grid->voxelCentreMm(v.voxel);
    p[v.axis] += v.t * vs;
    return p;
  }
  const std::uint32_t* loopOf(const SlotInfo& v) const { return loops[v.loop].data(); }
  // A slot's position before smoothing: an edge's, or its loop's mean.
  glm::dvec3 rawPosition(std::uint32_t slot) const {
    const SlotInfo& v = info[slot];
    if (v.axis != 3) return edgePosition(v);
    glm::dvec3 sum(0.0);
    const std::uint32_t* l = loopOf(v);
    for (int i = 0; i < v.loopSize; ++i) sum += edgePosition(info[l[i]]);
    return sum / double(v.loopSize);
  }

  std::uint32_t allocate(const SlotInfo& v) {
    std::uint32_t slot;
    if (!freeSlots.empty()) {
      slot = freeSlots.back();
      freeSlots.pop_back();
      info[slot] = v;
      alive[slot] = 1;
    } else {
      slot = std::uint32_t(info.size());
      info.push_back(v);
      position.push_back(glm::dvec3(0.0));
      normal.push_back(glm::dvec3(0.0));
      alive.push_back(1);
      mark.push_back(0);
      local.push_back(0);
    }
    return slot;
  }
  // A loop centre of cell `cell` over these vertices.
  std::uint32_t allocateCentre(const glm::ivec3& cell, const std::uint32_t* ids, int count) {
    std::uint32_t block;
    if (!freeLoops.empty()) {
      block = freeLoops.back();
      freeLoops.pop_back();
    } else {
      block = std::uint32_t(loops.size());
      loops.push_back({});
    }
    std::copy(ids, ids + count, loops[block].begin());
    return allocate(centreSlot(cell, count, block));
  }
  // A freed slot is reused only after the update that freed it: until then, old triangle
  // lists still name it and must not be mistaken for whatever would take its place.
  void release(std::uint32_t slot) {
    noteSlot(slot);
    alive[slot] = 0;
    if (info[slot].axis == 3) freeLoops.push_back(info[slot].loop);
    pendingFree.push_back(slot);
  }

  // Crossed edges owned by a cell brick's cells, diffed against what it had.
  void rebuildEdges(const glm::ivec3& cb, std::vector<std::uint32_t>& touched) {
    std::unique_ptr<CellBrick>& slot = bricks[brickIndex(cb)];
    const bool active = cellBrickActive(*grid, cb);
    if (!active && !slot) return;
    if (!slot) slot = std::make_unique<CellBrick>();
    CellBrick& b = *slot;
    const bool fresh = !b.fillsValid;
    if (!active) {
      for (std::uint32_t s : b.owned.slots()) release(s);
      b.owned.assign(noEdges());
      b.fillsValid = false;
      return;
    }
    loadBlock(*grid, cb, nextBlock);
    const FillBlock& block = nextBlock;
    // Which cells read a changed voxel (every cell when there is nothing to compare with).
    b.changed.fill(fresh ? ~std::uint64_t(0) : 0);
    bool any = fresh;
    if (!fresh) {
      for (int z = 0; z < kBlock; ++z)
        for (int y = 0; y < kBlock; ++y)
          for (int x = 0; x < kBlock; ++x) {
            if (blockFill(block, x, y, z) == blockFill(b.fills, x, y, z)) continue;
            any = true;
            for (int d = 0; d < 8; ++d) {
              const glm::ivec3 c(x - (d & 1), y - ((d >> 1) & 1), z - ((d >> 2) & 1));
              if (c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < kBrickEdge && c.y < kBrickEdge &&
                  c.z < kBrickEdge) {
                b.setChanged(cellIndex(c));
              }
            }
          }
    }
    if (!any) return;
    glm::ivec3 lo, hi;
    cellRange(*grid, cb, lo, hi);
    std::array<std::uint32_t, OwnedEdges::kEdges>& owned = ownedScratch;
    b.owned.expand(owned);
    for (int ci = 0; ci < kCells; ++ci) {
      if (!b.isChanged(ci)) continue;
      const glm::ivec3 l = cellInBrick(ci);
      const glm::ivec3 g = cb * kBrickEdge + l;
      const bool inRange = cellInRange(g, lo, hi);
      const Fill f0 = blockFill(block, l.x, l.y, l.z);
      for (int axis = 0; axis < 3; ++axis) {
        std::uint32_t& s = owned[std::size_t(3 * ci + axis)];
        glm::ivec3 n = l;
        ++n[axis];
        const Fill f1 = blockFill(block, n.x, n.y, n.z);
        if (!fresh && blockFill(b.fills, l.x, l.y, l.z) == f0 &&
            blockFill(b.fills, n.x, n.y, n.z) == f1) {
          continue;  // edge unchanged
        }
        const bool crosses = inRange && ((double(f0) > kIso) != (double(f1) > kIso));
        if (!crosses) {
          if (s != kNoVertex) release(s);
          s = kNoVertex;
          continue;
        }
        SlotInfo v;
        v.voxel = g;
        v.axis = std::uint8_t(axis);
        v.t = edgeParameter(f0, f1);
        if (s == kNoVertex) {
          s = allocate(v);
          touched.push_back(s);
        } else if (info[s].t != v.t) {
          info[s].t = v.t;
          touched.push_back(s);
        }
      }
    }
    b.owned.assign(owned);
  }
  static const std::array<std::uint32_t, OwnedEdges::kEdges>& noEdges() {
    static const std::array<std::uint32_t, OwnedEdges::kEdges> none = [] {
      std::array<std::uint32_t, OwnedEdges::kEdges> a;
      a.fill(kNoVertex);
      return a;
    }();
    return none;
  }

  std::uint32_t sharedVertex(const glm::ivec3& cell, int e) const {
    const glm::ivec3 owner = edgeStart(cell, e);
    const glm::ivec3 cb = brickOfCell(owner);
    return bricks[brickIndex(cb)]->owned.get(3 * cellIndex(owner - cb * kBrickEdge) + e / 4);
  }

  // Triangles of a cell brick's cells: a cell whose eight voxels kept their fill keeps its
  // triangles (and loop centres) as they were; the others are made again, and every vertex of
  // their old and new triangles is touched (its neighbourhood may have changed).
  void rebuildTriangles(const glm::ivec3& cb, std::vector<std::uint32_t>& touched) {
    CellBrick* b = bricks[brickIndex(cb)].get();
    if (!b) return;
    const bool active = cellBrickActive(*grid, cb);
    const FillBlock& block = nextBlock;  // as rebuildEdges read it: the grid has not changed since
    if (active) loadBlock(*grid, cb, nextBlock);
    if (active && b->fillsValid && block == b->fills) return;
    const bool hadOld = !b->triangles.empty() && b->fillsValid;
    noteBrick(brickIndex(cb));
    oldTriangles.swap(b->triangles);  // keeps both buffers' capacity between updates
    b->triangles.clear();
    const std::array<std::uint16_t, kCells + 1> oldBegin = b->cellBegin;
    const std::vector<glm::u32vec3>& old = oldTriangles;
    b->cellBegin.fill(0);
    const auto& table = mcTable();
    glm::ivec3 lo, hi;
    cellRange(*grid, cb, lo, hi);
    for (int ci = 0; ci < kCells; ++ci) {
      b->cellBegin[std::size_t(ci)] = std::uint16_t(b->triangles.size());
      const std::uint32_t oldFirst = hadOld ? oldBegin[std::size_t(ci)] : 0;
      const std::uint32_t oldEnd = hadOld ? oldBegin[std::size_t(ci) + 1] : 0;
      if (hadOld && active && !b->isChanged(ci)) {
        // Unchanged cells keep their triangles: copy the whole run of them at once.
        int last = ci;
        while (last + 1 < kCells && !b->isChanged(last + 1)) ++last;
        const std::uint32_t runEnd = oldBegin[std::size_t(last) + 1];
        const std::uint32_t shift = std::uint32_t(b->triangles.size()) - oldFirst;
        for (int k = ci + 1; k <= last; ++k)
          b->cellBegin[std::size_t(k)] = std::uint16_t(oldBegin[std::size_t(k)] + shift);
        b->triangles.insert(b->triangles.end(), old.begin() + oldFirst, old.begin() + runEnd);
        ci = last;
        continue;
      }
      const glm::ivec3 l = cellInBrick(ci);
      const int x = cb.x * kBrickEdge + l.x;
      const int y = cb.y * kBrickEdge + l.y;
      const int z = cb.z * kBrickEdge + l.z;
      {
        // Changed: its old triangles' vertices are touched, its old centres go.
        for (std::uint32_t k = oldFirst; k < oldEnd; ++k) {
          for (int c = 0; c < 3; ++c) {
            const std::uint32_t v = old[k][c];
            if (!alive[v]) continue;
            if (info[v].axis == 3) {
              if (c == 0 && (k == oldFirst || old[k - 1].x != v)) release(v);
            } else {
              touched.push_back(v);
            }
          }
        }
        if (!active || x < lo.x || y < lo.y || z < lo.z || x >= hi.x || y >= hi.y || z >= hi.z)
          continue;
        Fill corner[8];
        const int config = cellConfig(block, l, corner);
        if (config == 0 || config == 255) continue;
        const McCase& mc = table[std::size_t(config)];
        std::uint32_t ids[13];
        const auto firstNew = b->triangles.size();
        for (int loop = 0; loop < mc.loopCount; ++loop) {
          int count = 0;
          for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1];
               ++k) {
            ids[count++] = sharedVertex({x, y, z}, mc.edges[std::size_t(k)]);
          }
          std::uint32_t centre = kNoVertex;
          if (count > 4) centre = allocateCentre({x, y, z}, ids, count);
          appendLoopTriangles(b->triangles, ids, count, centre);
        }
        for (auto k = firstNew; k < b->triangles.size(); ++k) {
          for (int c = 0; c < 3; ++c) touched.push_back(b->triangles[k][c]);
        }
      }
    }
    b->cellBegin[kCells] = std::uint16_t(b->triangles.size());
    if (active) b->fills = block;
    b->fillsValid = active;
  }

  // Triangles around a vertex: in the four cells around its edge, or its own cell; in the order
  // they are stored (cell bricks by index, then cells, then each cell's list), which is the
  // order the first extraction sums normals in (smoothAll).
  template <typename Fn>
  void forEachIncident(std::uint32_t v, Fn&& fn) const {
    const SlotInfo& vi = info[v];
    const auto scanCell = [&](const CellBrick& b, int i) {
      for (std::uint32_t k = b.cellBegin[std::size_t(i)]; k < b.cellBegin[std::size_t(i) + 1];
           ++k) {
        const glm::u32vec3& t = b.triangles[k];
        if (t.x == v || t.y == v || t.z == v) fn(t);
      }
    };
    struct Cell {
      std::uint64_t key;
      const CellBrick* brick;
      int index;
    };
    Cell cells[4];
    int count = 0;
    const auto add = [&](const glm::ivec3& cell) {
      const glm::ivec3 cb = brickOfCell(cell);
      if (!validBrick(cb)) return;
      const std::size_t bi = brickIndex(cb);
      if (const CellBrick* b = bricks[bi].get()) {
        const int i = cellIndex(cell - cb * kBrickEdge);
        cells[count++] = {std::uint64_t(bi) * kCells + std::uint64_t(i), b, i};
      }
    };
    if (vi.axis == 3) {
      add(vi.voxel);
    } else {
      const int u = (vi.axis + 1) % 3;
      const int w = (vi.axis + 2) % 3;
      for (int du = 0; du < 2; ++du)
        for (int dw = 0; dw < 2; ++dw) {
          glm::ivec3 cell = vi.voxel;
          cell[u] -= du;
          cell[w] -= dw;
          add(cell);
        }
    }
    for (int i = 1; i < count; ++i)  // at most four: insertion
      for (int j = i; j > 0 && cells[j - 1].key > cells[j].key; --j)
        std::swap(cells[j - 1], cells[j]);
    for (int i = 0; i < count; ++i) scanCell(*cells[i].brick, cells[i].index);
  }

  // A vertex's neighbours, each once, in the order they first come in its triangles
  // (forEachIncident's order, each triangle's corners in order): smoothing sums their positions
  // in this order, here and in the first extraction (smoothAll).
  void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    forEachIncident(v, [&](const glm::u32vec3& t) {
      for (int c = 0; c < 3; ++c) {
        if (t[c] != v && std::find(out.begin(), out.end(), t[c]) == out.end()) out.push_back(t[c]);
      }
    });
  }

  // Smoothing and normals for the vertices within reach of `touched`. One Jacobi pass moves a
  // vertex by its neighbours' positions, and a loop centre is its loop's mean, so a vertex's
  // pass-j position depends on pass-(j-1) positions of its neighbours and of the loops of
  // neighbouring centres: one step of this dependency graph per pass. Over p passes a change
  // reaches p steps (those positions are kept), and they come out exact when computed on
  // 2p - 1 steps (farther vertices are read raw, which only spoils the discarded rim).
  std::size_t resmooth(const std::vector<std::uint32_t>& touched);  // surface_updater.cpp

  // The first extraction, of every cell brick, with the same vertex slots, triangles and
  // positions as update() of every brick would give (surface_updater_build.cpp).
  void buildAll();
  void buildBricksAndEdges();  // buildAll's parts
  void buildTriangles();
  // The first extraction's numbering: edge vertices first, then centres (brick order each).
  std::size_t edgeSlots = 0;
  std::vector<std::uint32_t> edgeFirst_;    // per cell brick: its first edge vertex (smoothAll's)
  std::vector<std::uint32_t> centreFirst_;  // per cell brick: its first loop centre
  // A cell brick's rows of cells with surface or crossed edges, from its block's inside bits.
  template <typename Fn>
  void forEachSurfaceRow(const glm::ivec3& cb, const FillBlock& block, Fn&& fn) const;
  // Every triangle that can hold an edge vertex cell brick cb owns, in forEachIncident's order.
  template <typename Fn>
  void forEachTriangleNear(const glm::ivec3& cb, Fn&& fn) const;
  void initSlot(std::uint32_t slot, const SlotInfo& v) {
    info[slot] = v;
    alive[slot] = 1;
    mark[slot] = 0;
    local[slot] = 0;
  }
  // Every per-slot array at `slots` slots (zeroed; alive set), and `centres` loop blocks.
  void sizeSlots(std::size_t slots, std::size_t centres);
  // Bytes held by the surface, structure by structure.
  SurfaceUpdater::Memory memory() const;
  void smoothAll();
  void brickNeighbours(std::size_t bi, std::uint32_t first, std::size_t count,
                       std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& out) const;
  void brickNormals(std::size_t bi, std::uint32_t first, std::size_t count);
  glm::ivec3 cellBrickOf(std::size_t index) const {
    return {int(index % std::size_t(cellBricks.x)) - 1,
            int(index / std::size_t(cellBricks.x) % std::size_t(cellBricks.y)) - 1,
            int(index / (std::size_t(cellBricks.x) * std::size_t(cellBricks.y))) - 1};
  }

  FillBlock nextBlock;  // the voxels a cell brick reads now (rebuildEdges, rebuildTriangles)
  std::array<std::uint32_t, OwnedEdges::kEdges> ownedScratch;  // rebuildEdges' dense table
  // Scratch of resmooth, kept between updates.
  std::vector<std::uint32_t> region, rowStart, rows, nb;
  PagedArray<std::uint32_t> local;  // per slot: its index in `region`
  std::vector<glm::u32vec3> oldTriangles;
  std::vector<int> depthOf;
  std::vector<glm::dvec3> cur;
  std::vector<double> curT, nextT;
};

}  // namespace osteon::geometry
