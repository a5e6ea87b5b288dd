// The updater's first extraction, of every cell brick, in parallel. It gives exactly what
// update() of every brick gives one brick after another (the same vertex slots, triangles,
// positions and normals), so later updates and the surface handed out do not depend on how
// the first one was made: cell bricks are extracted in parallel into their own lists, and
// vertex slots are then numbered in the order the serial update allocates them (every brick's
// edge vertices in brick order, then loop centres in brick order).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "surface_updater_impl.h"

namespace osteon::geometry {

namespace {

// A cell's loop of more than four vertices: triangles fanned from a centre vertex, which gets
// its slot once every brick's edge vertices have theirs.
struct PendingCentre {
  glm::ivec3 cell;
  std::uint32_t firstTriangle;  // its triangles: [first, first + loop size), centre first
  std::vector<std::uint32_t> loop;
};

}  // namespace

void SurfaceUpdater::Impl::reserveSlots(std::size_t slots) {
  info.reserve(slots);
  centreLoop.reserve(slots);
  position.reserve(slots);
  normal.reserve(slots);
  alive.reserve(slots);
  mark.reserve(slots);
  local.reserve(slots);
}

void SurfaceUpdater::Impl::buildAll() {
  buildBricksAndEdges();
  buildTriangles();
  smoothAll();
}

// Every active cell brick's fills and its crossed owned edges' vertices.
void SurfaceUpdater::Impl::buildBricksAndEdges() {
  const std::size_t count = bricks.size();
  constexpr std::size_t kGrain = 16;
  // Edges: each active cell brick's crossed owned edges, as (owned index, vertex), and how
  // many loop centres its cells will need (so every per-slot array is sized once).
  std::vector<std::vector<std::pair<std::uint32_t, VertexInfo>>> edges(count);
  std::vector<std::uint32_t> centreCount(count, 0);
  const auto& table = mcTable();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t bi = r.begin(); bi < r.end(); ++bi) {
                        const glm::ivec3 cb = cellBrickOf(bi);
                        if (!cellBrickActive(*grid, cb)) continue;
                        auto b = std::make_unique<CellBrick>();
                        b->owned.fill(kNoVertex);
                        b->cellBegin.fill(0);
                        b->changed.fill(1);
                        loadBlock(*grid, cb, b->fills);
                        const FillBlock& block = b->fills;
                        glm::ivec3 lo, hi;
                        cellRange(*grid, cb, lo, hi);
                        for (int ci = 0; ci < kCells; ++ci) {
                          const glm::ivec3 l = cellInBrick(ci);
                          const glm::ivec3 g = cb * kBrickEdge + l;
                          if (!cellInRange(g, lo, hi)) continue;
                          Fill corner[8];
                          const McCase& mc = table[std::size_t(cellConfig(block, l, corner))];
                          for (int loop = 0; loop < mc.loopCount; ++loop) {
                            centreCount[bi] += mc.loopBegin[std::size_t(loop) + 1] -
                                                   mc.loopBegin[std::size_t(loop)] >
                                               4;
                          }
                          const Fill f0 = blockFill(block, l.x, l.y, l.z);
                          for (int axis = 0; axis < 3; ++axis) {
                            glm::ivec3 n = l;
                            ++n[axis];
                            const Fill f1 = blockFill(block, n.x, n.y, n.z);
                            if ((double(f0) > kIso) == (double(f1) > kIso)) continue;
                            edges[bi].emplace_back(std::uint32_t(3 * ci + axis),
                                                   edgeVertexInfo(*grid, g, axis, f0, f1));
                          }
                        }
                        bricks[bi] = std::move(b);
                      }
                    });
  std::size_t slots = 0;
  for (std::size_t bi = 0; bi < count; ++bi) slots += edges[bi].size() + centreCount[bi];
  reserveSlots(slots);
  for (std::size_t bi = 0; bi < count; ++bi) {
    for (const auto& [k, v] : edges[bi]) bricks[bi]->owned[k] = allocate(v);
    std::vector<std::pair<std::uint32_t, VertexInfo>>().swap(edges[bi]);
  }
}

// Every cell brick's own triangles (the owned edges they read are all numbered now), and the
// loop centres of its long loops.
void SurfaceUpdater::Impl::buildTriangles() {
  const std::size_t count = bricks.size();
  constexpr std::size_t kGrain = 16;
  const auto& table = mcTable();
  std::vector<std::vector<PendingCentre>> centres(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kGrain),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t bi = r.begin(); bi < r.end(); ++bi) {
                        CellBrick* b = bricks[bi].get();
                        if (!b) continue;
                        const glm::ivec3 cb = cellBrickOf(bi);
                        glm::ivec3 lo, hi;
                        cellRange(*grid, cb, lo, hi);
                        for (int ci = 0; ci < kCells; ++ci) {
                          b->cellBegin[std::size_t(ci)] = std::uint32_t(b->triangles.size());
                          const glm::ivec3 l = cellInBrick(ci);
                          const glm::ivec3 g = cb * kBrickEdge + l;
                          if (!cellInRange(g, lo, hi)) continue;
                          Fill corner[8];
                          const int config = cellConfig(b->fills, l, corner);
                          if (config == 0 || config == 255) continue;
                          const McCase& mc = table[std::size_t(config)];
                          std::uint32_t ids[13];
                          for (int loop = 0; loop < mc.loopCount; ++loop) {
                            int n = 0;
                            for (int k = mc.loopBegin[std::size_t(loop)];
                                 k < mc.loopBegin[std::size_t(loop) + 1]; ++k) {
                              ids[n++] = sharedVertex(g, mc.edges[std::size_t(k)]);
                            }
                            if (n > 4)
                              centres[bi].push_back({g, std::uint32_t(b->triangles.size()),
                                                     std::vector<std::uint32_t>(ids, ids + n)});
                            appendLoopTriangles(b->triangles, ids, n,
                                                kNoVertex);  // the centre's slot comes later
                          }
                        }
                        b->cellBegin[kCells] = std::uint32_t(b->triangles.size());
                        b->fillsValid = true;
                      }
                    });
  for (std::size_t bi = 0; bi < count; ++bi) {
    CellBrick* b = bricks[bi].get();
    for (PendingCentre& c : centres[bi]) {
      const std::uint32_t slot = allocate({glm::dvec3(0.0), 3, 0.0, 0.0, 0, 0, c.cell});
      for (std::size_t i = 0; i < c.loop.size(); ++i) b->triangles[c.firstTriangle + i].x = slot;
      centreLoop[slot] = std::move(c.loop);
    }
    std::vector<PendingCentre>().swap(centres[bi]);
    // A cell brick with no surface gives its memory back.
    if (b && b->triangles.empty() &&
        std::all_of(b->owned.begin(), b->owned.end(),
                    [](std::uint32_t s) { return s == kNoVertex; })) {
      bricks[bi].reset();
    }
  }
}

// resmooth() over every vertex: every slot is touched, in slot order, at depth 0, so the
// region is all slots and no vertex is read raw.
void SurfaceUpdater::Impl::smoothAll() {
  const std::size_t n = info.size();
  ++epoch;
  constexpr std::size_t kGrain = 4096;
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  std::vector<std::vector<std::uint32_t>> chunkRows(chunks), chunkStarts(chunks);
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
    std::vector<std::uint32_t> out;
    for (std::size_t v = c * kGrain; v < std::min(n, (c + 1) * kGrain); ++v) {
      mark[v] = epoch;
      local[v] = std::uint32_t(v);
      neighbours(std::uint32_t(v), out);
      chunkStarts[c].push_back(std::uint32_t(out.size()));
      chunkRows[c].insert(chunkRows[c].end(), out.begin(), out.end());
    }
  });
  rowStart.assign(1, 0);
  rowStart.reserve(n + 1);
  rows.clear();
  for (std::size_t c = 0; c < chunks; ++c) {
    for (const std::uint32_t size : chunkStarts[c]) rowStart.push_back(rowStart.back() + size);
    rows.insert(rows.end(), chunkRows[c].begin(), chunkRows[c].end());
    std::vector<std::uint32_t>().swap(chunkRows[c]);
  }
  const auto raw = [&](std::uint32_t slot) {
    if (info[slot].axis != 3) return positionOf(info[slot]);
    glm::dvec3 sum(0.0);
    for (std::uint32_t l : centreLoop[slot]) sum += positionOf(info[l]);
    return sum / double(centreLoop[slot].size());
  };
  std::vector<glm::dvec3> at(n);
  std::vector<double> t(n), nextT2(n);
  const auto each = [&](auto&& fn) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kGrain),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) fn(i);
                      });
  };
  each([&](std::size_t i) {
    t[i] = info[i].t;
    at[i] = raw(std::uint32_t(i));
  });
  for (int pass = 0; pass < options.smoothIterations; ++pass) {
    const double step = options.taubin && pass % 2 == 1 ? options.mu : options.lambda;
    each([&](std::size_t i) {
      const VertexInfo& v = info[i];
      if (v.axis == 3) return;
      double mean = 0.0;
      for (std::uint32_t k = rowStart[i]; k < rowStart[i + 1]; ++k) mean += at[rows[k]][v.axis];
      mean /= double(rowStart[i + 1] - rowStart[i]);
      nextT2[i] = std::clamp(t[i] + step * (mean - at[i][v.axis]) / v.lengthMm, kEdgeMargin,
                             1.0 - kEdgeMargin);
    });
    each([&](std::size_t i) {
      VertexInfo v = info[i];
      if (v.axis == 3) return;
      t[i] = nextT2[i];
      v.t = t[i];
      at[i] = positionOf(v);
    });
    each([&](std::size_t i) {
      if (info[i].axis != 3) return;
      glm::dvec3 sum(0.0);
      for (std::uint32_t l : centreLoop[i]) sum += at[l];
      at[i] = sum / double(centreLoop[i].size());
    });
  }
  position = std::move(at);
  each([&](std::size_t v) {
    glm::dvec3 sum(0.0);
    forEachIncident(std::uint32_t(v), [&](const glm::u32vec3& tri) {
      sum += glm::cross(position[tri.y] - position[tri.x], position[tri.z] - position[tri.x]);
    });
    const double len = glm::length(sum);
    normal[v] = len > 0.0 ? sum / len : glm::dvec3(0.0);
  });
  // Later updates touch a few hundred vertices: their scratch need not stay at this size.
  std::vector<std::uint32_t>().swap(rows);
  std::vector<std::uint32_t>().swap(rowStart);
}

}  // namespace osteon::geometry
