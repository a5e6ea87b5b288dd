// The updater's first extraction, of every cell brick, in parallel. It gives exactly what
// update() of every brick gives one brick after another (the same vertex slots, triangles,
// positions and normals), so later updates and the surface handed out do not depend on how
// the first one was made: cell bricks are extracted in parallel into their own lists, and
// vertex slots are then numbered in the order the serial update allocates them (every brick's
// edge vertices in brick order, then loop centres in brick order). Numbered so, a brick's edge
// vertices are one run of slots, which lets smoothing and normals work brick by brick from the
// triangles near each brick, where update() gathers them vertex by vertex.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "surface_cases.h"
#include "surface_updater_impl.h"

namespace osteon::geometry {

namespace {

constexpr std::size_t kBrickGrain = 16;

template <typename Fn>
void eachBrick(std::size_t count, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kBrickGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t bi = r.begin(); bi < r.end(); ++bi) fn(bi);
                    });
}

}  // namespace

void SurfaceUpdater::Impl::sizeSlots(std::size_t slots, std::size_t centres) {
  info.growTo(slots);
  position.growTo(slots);
  normal.growTo(slots);
  alive.growTo(slots);
  mark.growTo(slots);
  local.growTo(slots);
  loops.growTo(centres);
}

// Inside bits of a cell brick's block rows (RowMasks): a cell has surface when its eight
// corners' bits are not all alike, an edge crosses when its two ends' bits differ, eight cells
// at a time; only those cells are looked up in the case table. fn(row, mixed, edges, corners)
// for every row of cells in range (row: its first cell's index) with surface or crossings:
// mixed cells and crossed owned edges per axis as bits by x, and the row's corner rows.
template <typename Fn>
void SurfaceUpdater::Impl::forEachSurfaceRow(const glm::ivec3& cb, const FillBlock& block,
                                             Fn&& fn) const {
  RowMasks insideRows;
  for (int r = 0; r < kBlock * kBlock; ++r) {
    const Fill* f = block.data() + r * kBlock;
    insideRows[std::size_t(r)] =
        std::uint16_t(insideOf8(f) | (std::uint32_t(f[kCellBrick] > kInsideAbove) << kCellBrick));
  }
  glm::ivec3 lo, hi;
  cellRange(*grid, cb, lo, hi);
  const glm::ivec3 first = glm::max(lo - cb * kBrickEdge, glm::ivec3(0));
  const glm::ivec3 last = glm::min(hi - cb * kBrickEdge, glm::ivec3(kBrickEdge));
  const std::uint32_t inRangeX = ((1u << last.x) - 1u) & ~((1u << first.x) - 1u);
  for (int z = first.z; z < last.z; ++z)
    for (int y = first.y; y < last.y; ++y) {
      std::uint32_t r[4];
      rowCorners(insideRows, y, z, r);
      const std::uint32_t all = r[0] & r[1] & r[2] & r[3], any = r[0] | r[1] | r[2] | r[3];
      const std::uint32_t mixed = ~((all & (all >> 1)) | (~any & ~(any >> 1))) & inRangeX;
      const std::uint32_t edges[3] = {(r[0] ^ (r[0] >> 1)) & inRangeX, (r[0] ^ r[1]) & inRangeX,
                                      (r[0] ^ r[2]) & inRangeX};
      if ((mixed | edges[0] | edges[1] | edges[2]) == 0) continue;
      fn(kBrickEdge * (y + kBrickEdge * z), mixed, edges, r);
    }
}

void SurfaceUpdater::Impl::buildAll() {
  buildBricksAndEdges();
  buildTriangles();
  smoothAll();
}

// Every active cell brick's fills and which of its owned edges cross; then every crossed edge's
// vertex numbered, brick after brick in edge order (as update() of every brick numbers them),
// each array sized once and written in parallel.
void SurfaceUpdater::Impl::buildBricksAndEdges() {
  const std::size_t count = bricks.size();
  std::vector<std::uint32_t> edgeFirst(count + 1, 0), centreFirst(count + 1, 0);
  const auto& packed = packedCaseCounts();
  eachBrick(count, [&](std::size_t bi) {
    const glm::ivec3 cb = cellBrickOf(bi);
    if (!cellBrickActive(*grid, cb)) return;
    std::unique_ptr<CellBrick> b(new CellBrick);  // not zeroed: every field is written here
    b->changed.fill(0);                           // or in buildTriangles
    loadBlock(*grid, cb, b->fills);
    std::array<std::uint64_t, OwnedEdges::kWords> crossed{};
    std::uint64_t sums = 0;  // the cases' counts in 16-bit lanes: triangles, then centres
    forEachSurfaceRow(cb, b->fills,
                      [&](int row, std::uint32_t mixed, const std::uint32_t* edges,
                          const std::uint32_t(&corners)[4]) {
                        for (int axis = 0; axis < 3; ++axis)
                          for (std::uint32_t m = edges[axis]; m; m &= m - 1) {
                            const int e = 3 * (row + __builtin_ctz(m)) + axis;
                            crossed[std::size_t(e >> 6)] |= std::uint64_t(1) << (e & 63);
                          }
                        const std::uint64_t configs = rowConfigs(corners);
                        for (std::uint32_t m = mixed; m; m &= m - 1) {
                          // The cell's case kept for buildTriangles where its range will go.
                          const int x = __builtin_ctz(m), ci = row + x;
                          const auto config = std::uint16_t((configs >> (8 * x)) & 0xffu);
                          b->setChanged(ci);
                          b->cellBegin[std::size_t(ci)] = config;
                          sums += packed[config];
                        }
                      });
    const std::size_t triangles = sums & 0xffffu;
    const auto centres = std::uint32_t((sums >> 16) & 0xffffu);
    b->owned.setMask(crossed);
    b->triangles.reserve(triangles);
    edgeFirst[bi + 1] = std::uint32_t(b->owned.count());
    centreFirst[bi + 1] = centres;
    bricks[bi] = std::move(b);
  });
  for (std::size_t bi = 0; bi < count; ++bi) {
    edgeFirst[bi + 1] += edgeFirst[bi];
    centreFirst[bi + 1] += centreFirst[bi];
  }
  edgeSlots = edgeFirst[count];
  edgeFirst_ = edgeFirst;
  sizeSlots(std::size_t(edgeFirst[count]) + centreFirst[count], centreFirst[count]);
  eachBrick(count, [&](std::size_t bi) {
    CellBrick* b = bricks[bi].get();
    if (!b) return;
    const glm::ivec3 cb = cellBrickOf(bi);
    std::uint32_t slot = edgeFirst[bi];
    std::vector<std::uint32_t>& slots = b->owned.slots();
    std::size_t k = 0;
    b->owned.forEach([&](int e, std::uint32_t) {
      const int ci = e / 3, axis = e % 3;
      const glm::ivec3 l = cellInBrick(ci);
      glm::ivec3 n = l;
      ++n[axis];
      SlotInfo v;
      v.voxel = cb * kBrickEdge + l;
      v.axis = std::uint8_t(axis);
      v.t = edgeParameter(blockFill(b->fills, l.x, l.y, l.z), blockFill(b->fills, n.x, n.y, n.z));
      initSlot(slot, v);
      position[slot] = edgePosition(v);  // as it is before smoothing
      slots[k++] = slot++;
    });
  });
  centreFirst_.swap(centreFirst);
}

// Every cell brick's own triangles (the owned edges they read are all numbered now), and the
// loop centres of its long loops, numbered after every edge vertex in brick order.
void SurfaceUpdater::Impl::buildTriangles() {
  const std::size_t count = bricks.size();
  const auto& table = mcTable();
  eachBrick(count, [&](std::size_t bi) {
    CellBrick* b = bricks[bi].get();
    if (!b) return;
    const glm::ivec3 cb = cellBrickOf(bi);
    // Vertex slots of the brick's own edges in a table, and of the bricks above once asked for
    // (a cell's edges lie in its brick or in the next along each axis): sharedVertex without
    // looking up the brick each time.
    std::array<std::uint32_t, OwnedEdges::kEdges> own;
    b->owned.expand(own);
    const OwnedEdges* above[8] = {&b->owned};
    const auto vertexOf = [&](const glm::ivec3& l, int e) {
      const glm::ivec3 o =
          l + glm::ivec3(kEdgeStartOffset[std::size_t(e)][0], kEdgeStartOffset[std::size_t(e)][1],
                         kEdgeStartOffset[std::size_t(e)][2]);
      const int d = (o.x >> 3) | ((o.y >> 3) << 1) | ((o.z >> 3) << 2);
      const int edge = 3 * cellIndex(o & (kBrickEdge - 1)) + e / 4;
      if (d == 0) return own[std::size_t(edge)];
      if (!above[d]) {
        const glm::ivec3 up = cb + glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1);
        above[d] = &bricks[brickIndex(up)]->owned;  // it owns this crossed edge: it exists
      }
      return above[d]->get(edge);
    };
    std::uint32_t centre = centreFirst_[bi];
    int nextCell = 0;
    // Cells with surface (changed bits) and their cases (in cellBegin), as counted.
    for (int w = 0; w < kCells / 64; ++w)
      for (std::uint64_t m = b->changed[std::size_t(w)]; m; m &= m - 1) {
        const int ci = 64 * w + __builtin_ctzll(m);
        const int config = b->cellBegin[std::size_t(ci)];
        while (nextCell <= ci)
          b->cellBegin[std::size_t(nextCell++)] = std::uint16_t(b->triangles.size());
        const glm::ivec3 l = cellInBrick(ci);
        const glm::ivec3 g = cb * kBrickEdge + l;
        const McCase& mc = table[std::size_t(config)];
        std::uint32_t ids[13];
        for (int loop = 0; loop < mc.loopCount; ++loop) {
          int n = 0;
          for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1];
               ++k)
            ids[n++] = vertexOf(l, mc.edges[std::size_t(k)]);
          std::uint32_t slot = kNoVertex;
          if (n > 4) {
            std::copy(ids, ids + n, loops[centre].begin());
            slot = std::uint32_t(edgeSlots) + centre;
            initSlot(slot, centreSlot(g, n, centre++));
            // Its loop's mean (rawPosition) from their raw positions, set when numbered.
            glm::dvec3 sum(0.0);
            for (int i = 0; i < n; ++i) sum += position[ids[i]];
            position[slot] = sum / double(n);
          }
          appendLoopTriangles(b->triangles, ids, n, slot);
        }
      }
    while (nextCell <= kCells)
      b->cellBegin[std::size_t(nextCell++)] = std::uint16_t(b->triangles.size());
    b->changed.fill(~std::uint64_t(0));
    b->fillsValid = true;
    // A cell brick with no surface gives its memory back.
    if (b->triangles.empty() && b->owned.count() == 0) bricks[bi].reset();
  });
}

template <typename Fn>
void SurfaceUpdater::Impl::forEachTriangleNear(const glm::ivec3& cb, Fn&& fn) const {
  // An edge's four cells lie in its owner's brick and in the ones below along the two other
  // axes: those bricks in ascending index, in each only the cells next to cb.
  static constexpr int kBelow[7][3] = {{0, -1, -1}, {-1, 0, -1}, {0, 0, -1}, {-1, -1, 0},
                                       {0, -1, 0},  {-1, 0, 0},  {0, 0, 0}};
  for (const auto& d : kBelow) {
    const glm::ivec3 below = cb + glm::ivec3(d[0], d[1], d[2]);
    if (!validBrick(below)) continue;
    const CellBrick* b = bricks[brickIndex(below)].get();
    if (!b) continue;
    if (d[0] == 0 && d[1] == 0 && d[2] == 0) {
      for (const glm::u32vec3& t : b->triangles) fn(t);
      continue;
    }
    const int x0 = d[0] ? kBrickEdge - 1 : 0, y0 = d[1] ? kBrickEdge - 1 : 0,
              z0 = d[2] ? kBrickEdge - 1 : 0;
    for (int z = z0; z < kBrickEdge; ++z)
      for (int y = y0; y < kBrickEdge; ++y) {
        const int row = kBrickEdge * (y + kBrickEdge * z);
        const std::uint32_t first = b->cellBegin[std::size_t(row + x0)];
        const std::uint32_t last = b->cellBegin[std::size_t(row + kBrickEdge)];
        for (std::uint32_t k = first; k < last; ++k) fn(b->triangles[k]);
      }
  }
}

// The neighbours of the edge vertices cell brick bi owns (slots first .. first + count), as
// neighbours() lists them, appended to `out` with a start per vertex.
void SurfaceUpdater::Impl::brickNeighbours(std::size_t bi, std::uint32_t first, std::size_t count,
                                           std::vector<std::uint32_t>& start,
                                           std::vector<std::uint32_t>& out) const {
  if (count == 0) return;
  // An edge vertex lies in at most two triangles of each of its four cells (its edge is in one
  // loop of a cell's case, and a loop's triangulation puts a vertex in one or two triangles).
  constexpr std::size_t kMaxAround = 16;
  // Each owned vertex's triangles' other corners in order, then each once in the order they
  // first come.
  std::array<std::uint32_t, OwnedEdges::kEdges * kMaxAround> found;
  std::array<std::uint32_t, OwnedEdges::kEdges> size;
  std::fill_n(size.begin(), count, 0u);
  forEachTriangleNear(cellBrickOf(bi), [&](const glm::u32vec3& t) {
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = t[c] - first;
      if (i >= count) continue;
      std::uint32_t* other = found.data() + i * kMaxAround + size[i];
      other[0] = t[c == 0 ? 1 : 0];
      other[1] = t[c == 2 ? 1 : 2];
      size[i] += 2;
    }
  });
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t* in = found.data() + i * kMaxAround;
    std::uint32_t kept[kMaxAround];
    int kn = 0;
    for (std::uint32_t k = 0; k < size[i]; ++k) {
      bool seen = false;
      for (int j = 0; j < kn; ++j) seen |= kept[j] == in[k];
      if (!seen) kept[kn++] = in[k];
    }
    out.insert(out.end(), kept, kept + kn);
    start.push_back(std::uint32_t(out.size()));
  }
}

// The normals of the edge vertices cell brick bi owns and of its loop centres, each the sum
// of its triangles' area-weighted normals in forEachIncident's order. Loop centres are in
// their own brick's triangles only, always first (appendLoopTriangles).
void SurfaceUpdater::Impl::brickNormals(std::size_t bi, std::uint32_t first, std::size_t count) {
  const std::uint32_t centreBase = std::uint32_t(edgeSlots) + centreFirst_[bi];
  const std::size_t centres = centreFirst_[bi + 1] - centreFirst_[bi];
  if (count == 0 && centres == 0) return;
  std::array<glm::dvec3, OwnedEdges::kEdges> sum;
  std::array<glm::dvec3, 2 * kCells> centreSum;  // at most two long loops per cell
  std::fill_n(sum.begin(), count, glm::dvec3(0.0));
  std::fill_n(centreSum.begin(), centres, glm::dvec3(0.0));
  forEachTriangleNear(cellBrickOf(bi), [&](const glm::u32vec3& tri) {
    const std::size_t a = tri.x - first, b = tri.y - first, c = tri.z - first;
    const std::size_t centre = tri.x - centreBase;
    if (a >= count && b >= count && c >= count && centre >= centres) return;
    const glm::dvec3 w =
        glm::cross(position[tri.y] - position[tri.x], position[tri.z] - position[tri.x]);
    if (centre < centres) centreSum[centre] += w;
    if (a < count) sum[a] += w;
    if (b < count) sum[b] += w;
    if (c < count) sum[c] += w;
  });
  const auto unit = [](const glm::dvec3& v) {
    const double len = glm::length(v);
    return len > 0.0 ? v / len : glm::dvec3(0.0);
  };
  for (std::size_t i = 0; i < count; ++i) normal[first + i] = unit(sum[i]);
  for (std::size_t i = 0; i < centres; ++i) normal[centreBase + i] = unit(centreSum[i]);
}

// resmooth() over every vertex, with what it gathers per vertex made brick by brick instead:
// each cell brick's edge vertices are numbered in one run (edgeFirst_), so the triangles near
// the brick (forEachTriangleNear) give every one of them its neighbours, and later its normal
// summed in forEachIncident's order, with no search per vertex. Loop centres take no smoothing
// step of their own (they follow their loop's mean).
void SurfaceUpdater::Impl::smoothAll() {
  const std::size_t n = info.size();
  constexpr std::size_t kGrain = 4096;
  const auto eachSlot = [&](std::size_t first, std::size_t last, auto&& fn) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t v = r.begin(); v < r.end(); ++v) fn(v);
                      });
  };
  // Cell bricks with surface, in order, a run of them per chunk; the edge vertices they own are
  // the chunk's run of slots.
  std::vector<std::uint32_t> owners;
  for (std::size_t bi = 0; bi < bricks.size(); ++bi)
    if (bricks[bi]) owners.push_back(std::uint32_t(bi));
  constexpr std::size_t kBricksPerChunk = 16;
  struct Chunk {
    std::size_t firstBrick, endBrick;
    std::vector<std::uint32_t> start, rows;  // neighbours of slot first + i: rows[start[i]..)
  };
  std::vector<Chunk> chunks;
  for (std::size_t b = 0; b < owners.size(); b += kBricksPerChunk)
    chunks.push_back({b, std::min(owners.size(), b + kBricksPerChunk), {}, {}});
  const auto eachOwner = [&](auto&& fn) {
    tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t c) {
      for (std::size_t k = chunks[c].firstBrick; k < chunks[c].endBrick; ++k) {
        const std::size_t bi = owners[k];
        fn(chunks[c], bi, edgeFirst_[bi], bricks[bi]->owned.count());
      }
    });
  };
  const auto slotOfChunk = [&](const Chunk& c) { return edgeFirst_[owners[c.firstBrick]]; };

  if (options.smoothIterations > 0) {
    eachOwner([&](Chunk& chunk, std::size_t bi, std::uint32_t first, std::size_t count) {
      if (chunk.start.empty()) {  // the chunk's first brick: room for all of its rows
        const std::size_t slots =
            edgeFirst_[owners[chunk.endBrick - 1] + 1] - edgeFirst_[owners[chunk.firstBrick]];
        chunk.start.reserve(slots + 1);
        chunk.rows.reserve(7 * slots);  // about six neighbours each on a smooth surface
        chunk.start.push_back(0);
      }
      brickNeighbours(bi, first, count, chunk.start, chunk.rows);
    });
  }
  // Each edge vertex's parameter along its edge, one buffer read and the other written by
  // turns (the first pass reads info's). A pass moves a vertex along its own axis only, so only
  // that coordinate is written again, as edgePosition computes it.
  std::vector<double> tEven(options.smoothIterations > 0 ? edgeSlots : 0), tOdd(tEven.size());
  const glm::dvec3 origin = grid->originMm();
  for (int pass = 0; pass < options.smoothIterations; ++pass) {
    const double step = options.taubin && pass % 2 == 1 ? options.mu : options.lambda;
    const std::vector<double>& before = pass % 2 == 0 ? tOdd : tEven;
    std::vector<double>& after = pass % 2 == 0 ? tEven : tOdd;
    tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t c) {
      const Chunk& chunk = chunks[c];
      const std::size_t first = slotOfChunk(chunk);
      for (std::size_t row = 0; row + 1 < chunk.start.size(); ++row) {
        const std::size_t i = first + row;
        const SlotInfo& v = info[i];
        double mean = 0.0;
        for (std::uint32_t k = chunk.start[row]; k < chunk.start[row + 1]; ++k)
          mean += position[chunk.rows[k]][v.axis];
        mean /= double(chunk.start[row + 1] - chunk.start[row]);
        const double t = pass == 0 ? v.t : before[i];
        after[i] = std::clamp(t + step * (mean - position[i][v.axis]) / vs, kEdgeMargin,
                              1.0 - kEdgeMargin);
      }
    });
    eachSlot(0, edgeSlots, [&](std::size_t i) {
      const SlotInfo& v = info[i];
      const int a = v.axis;
      position[i][a] = (origin[a] + (double(v.voxel[a]) + 0.5) * vs) + after[i] * vs;
    });
    eachSlot(edgeSlots, n, [&](std::size_t i) {
      const SlotInfo& c = info[i];
      glm::dvec3 sum(0.0);
      const std::uint32_t* l = loopOf(c);
      for (int k = 0; k < c.loopSize; ++k) sum += position[l[k]];
      position[i] = sum / double(c.loopSize);
    });
  }
  for (Chunk& chunk : chunks) {  // the neighbour lists are done with
    std::vector<std::uint32_t>().swap(chunk.start);
    std::vector<std::uint32_t>().swap(chunk.rows);
  }
  eachOwner([&](Chunk&, std::size_t bi, std::uint32_t first, std::size_t count) {
    brickNormals(bi, first, count);
  });
  std::vector<std::uint32_t>().swap(edgeFirst_);
  std::vector<std::uint32_t>().swap(centreFirst_);
}

}  // namespace osteon::geometry
