// The updater's first extraction, of every cell brick, in parallel. It gives exactly what
// update() of every brick gives one brick after another (the same vertex slots, triangles,
// positions and normals), so later updates and the surface handed out do not depend on how
// the first one was made: cell bricks are extracted in parallel into their own lists, and
// vertex slots are then numbered in the order the serial update allocates them (every brick's
// edge vertices in brick order, then loop centres in brick order).
#include <bitset>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "surface_updater_impl.h"

namespace osteon::geometry {

namespace {

// Triangles a loop of n vertices gives (appendLoopTriangles): 1 for 3, 2 for 4, a fan of n.
int loopTriangles(int n) {
  return n == 3 ? 1 : n == 4 ? 2 : n;
}

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
  const auto& table = mcTable();
  eachBrick(count, [&](std::size_t bi) {
    const glm::ivec3 cb = cellBrickOf(bi);
    if (!cellBrickActive(*grid, cb)) return;
    auto b = std::make_unique<CellBrick>();
    loadBlock(*grid, cb, b->fills);
    const FillBlock& block = b->fills;
    glm::ivec3 lo, hi;
    cellRange(*grid, cb, lo, hi);
    std::bitset<OwnedEdges::kEdges> crossed;
    std::uint32_t centres = 0;
    std::size_t triangles = 0;
    // Inside bits of the block's rows (bit x of row y + 9 z): a cell has surface when its eight
    // corners' bits are not all alike, an edge crosses when its two ends' bits differ, eight
    // cells at a time; only those cells are looked up in the case table.
    std::array<std::uint16_t, kBlock * kBlock> insideRows;
    for (int r = 0; r < kBlock * kBlock; ++r) {
      std::uint32_t m = 0;
      for (int x = 0; x < kBlock; ++x)
        m |= std::uint32_t(block[std::size_t(r * kBlock + x)] > kInsideAbove) << x;
      insideRows[std::size_t(r)] = std::uint16_t(m);
    }
    const glm::ivec3 first = glm::max(lo - cb * kBrickEdge, glm::ivec3(0));
    const glm::ivec3 last = glm::min(hi - cb * kBrickEdge, glm::ivec3(kBrickEdge));
    const std::uint32_t inRangeX = ((1u << last.x) - 1u) & ~((1u << first.x) - 1u);
    for (int z = first.z; z < last.z; ++z)
      for (int y = first.y; y < last.y; ++y) {
        const std::uint32_t r0 = insideRows[std::size_t(y + kBlock * z)];
        const std::uint32_t r1 = insideRows[std::size_t(y + 1 + kBlock * z)];
        const std::uint32_t r2 = insideRows[std::size_t(y + kBlock * (z + 1))];
        const std::uint32_t r3 = insideRows[std::size_t(y + 1 + kBlock * (z + 1))];
        const std::uint32_t all = r0 & r1 & r2 & r3, any = r0 | r1 | r2 | r3;
        const std::uint32_t mixed = ~((all & (all >> 1)) | (~any & ~(any >> 1))) & inRangeX;
        const std::uint32_t edges[3] = {(r0 ^ (r0 >> 1)) & inRangeX, (r0 ^ r1) & inRangeX,
                                        (r0 ^ r2) & inRangeX};
        const int row = kBrickEdge * (y + kBrickEdge * z);
        for (int axis = 0; axis < 3; ++axis)
          for (std::uint32_t m = edges[axis]; m; m &= m - 1)
            crossed.set(std::size_t(3 * (row + __builtin_ctz(m)) + axis));
        for (std::uint32_t m = mixed; m; m &= m - 1) {
          const int ci = row + __builtin_ctz(m);
          b->setChanged(ci);  // buildTriangles' cells, for now
          Fill corner[8];
          const McCase& mc = table[std::size_t(cellConfig(block, cellInBrick(ci), corner))];
          for (int loop = 0; loop < mc.loopCount; ++loop) {
            const int n = mc.loopBegin[std::size_t(loop) + 1] - mc.loopBegin[std::size_t(loop)];
            centres += n > 4;
            triangles += std::size_t(loopTriangles(n));
          }
        }
      }
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
    glm::ivec3 lo, hi;
    cellRange(*grid, cb, lo, hi);
    std::uint32_t centre = centreFirst_[bi];
    for (int ci = 0; ci < kCells; ++ci) {
      b->cellBegin[std::size_t(ci)] = std::uint16_t(b->triangles.size());
      if (!b->isChanged(ci)) continue;  // no surface in it (or out of range)
      const glm::ivec3 l = cellInBrick(ci);
      const glm::ivec3 g = cb * kBrickEdge + l;
      Fill corner[8];
      const int config = cellConfig(b->fills, l, corner);
      const McCase& mc = table[std::size_t(config)];
      std::uint32_t ids[13];
      for (int loop = 0; loop < mc.loopCount; ++loop) {
        int n = 0;
        for (int k = mc.loopBegin[std::size_t(loop)]; k < mc.loopBegin[std::size_t(loop) + 1]; ++k)
          ids[n++] = sharedVertex(g, mc.edges[std::size_t(k)]);
        std::uint32_t slot = kNoVertex;
        if (n > 4) {
          std::copy(ids, ids + n, loops[centre].begin());
          slot = std::uint32_t(edgeSlots) + centre;
          initSlot(slot, centreSlot(g, n, centre++));
        }
        appendLoopTriangles(b->triangles, ids, n, slot);
      }
    }
    b->cellBegin[kCells] = std::uint16_t(b->triangles.size());
    b->changed.fill(~std::uint64_t(0));
    b->fillsValid = true;
    // A cell brick with no surface gives its memory back.
    if (b->triangles.empty() && b->owned.count() == 0) bricks[bi].reset();
  });
  std::vector<std::uint32_t>().swap(centreFirst_);
}

// resmooth() over every vertex: every slot is touched, in slot order, at depth 0, so the
// region is all slots and no vertex is read raw. The positions are smoothed in place.
void SurfaceUpdater::Impl::smoothAll() {
  const std::size_t n = info.size();
  ++epoch;
  constexpr std::size_t kGrain = 4096;
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  // Each chunk's neighbour lists, kept per chunk: no second copy of them all at once.
  std::vector<std::vector<std::uint32_t>> chunkRows(chunks), chunkStarts(chunks);
  const auto eachChunk = [&](auto&& fn) {
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      for (std::size_t v = c * kGrain; v < std::min(n, (c + 1) * kGrain); ++v) fn(c, v);
    });
  };
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::vector<std::uint32_t> out;
    std::vector<std::uint32_t>& chunk = chunkRows[c];
    std::vector<std::uint32_t>& starts = chunkStarts[c];
    starts.push_back(0);
    for (std::size_t v = c * kGrain; v < std::min(n, (c + 1) * kGrain); ++v) {
      mark[v] = epoch;
      local[v] = std::uint32_t(v);
      neighbours(std::uint32_t(v), out);
      chunk.insert(chunk.end(), out.begin(), out.end());
      starts.push_back(std::uint32_t(chunk.size()));
    }
  });
  std::vector<double> t(n), nextT2(n);
  eachChunk([&](std::size_t, std::size_t i) {
    t[i] = info[i].axis == 3 ? 0.0 : info[i].t;
    position[i] = rawPosition(std::uint32_t(i));
  });
  for (int pass = 0; pass < options.smoothIterations; ++pass) {
    const double step = options.taubin && pass % 2 == 1 ? options.mu : options.lambda;
    eachChunk([&](std::size_t c, std::size_t i) {
      const SlotInfo& v = info[i];
      if (v.axis == 3) return;
      const std::vector<std::uint32_t>& chunk = chunkRows[c];
      const std::size_t row = i - c * kGrain;
      const std::uint32_t first = chunkStarts[c][row], last = chunkStarts[c][row + 1];
      double mean = 0.0;
      for (std::uint32_t k = first; k < last; ++k) mean += position[chunk[k]][v.axis];
      mean /= double(last - first);
      nextT2[i] = std::clamp(t[i] + step * (mean - position[i][v.axis]) / vs, kEdgeMargin,
                             1.0 - kEdgeMargin);
    });
    eachChunk([&](std::size_t, std::size_t i) {
      SlotInfo v = info[i];
      if (v.axis == 3) return;
      t[i] = nextT2[i];
      v.t = t[i];
      position[i] = edgePosition(v);
    });
    eachChunk([&](std::size_t, std::size_t i) {
      const SlotInfo& c = info[i];
      if (c.axis != 3) return;
      glm::dvec3 sum(0.0);
      const std::uint32_t* l = loopOf(c);
      for (int k = 0; k < c.loopSize; ++k) sum += position[l[k]];
      position[i] = sum / double(c.loopSize);
    });
  }
  eachChunk([&](std::size_t, std::size_t v) {
    glm::dvec3 sum(0.0);
    forEachIncident(std::uint32_t(v), [&](const glm::u32vec3& tri) {
      sum += glm::cross(position[tri.y] - position[tri.x], position[tri.z] - position[tri.x]);
    });
    const double len = glm::length(sum);
    normal[v] = len > 0.0 ? sum / len : glm::dvec3(0.0);
  });
}

}  // namespace osteon::geometry
