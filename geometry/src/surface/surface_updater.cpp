#include "osteon/geometry/surface/surface_updater.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "osteon/core/error.h"
#include "osteon/core/timing.h"
#include "surface_updater_impl.h"

namespace osteon::geometry {

SurfaceUpdater::SurfaceUpdater(const VoxelGrid& grid, const SurfaceOptions& options)
    : SurfaceUpdater(grid, options, grid) {}

SurfaceUpdater::SurfaceUpdater(const VoxelGrid& grid, const SurfaceOptions& options,
                               const VoxelGrid& asItWas)
    : impl_(std::make_unique<Impl>()) {
  validateSurfaceOptions(options);
  if (asItWas.dims() != grid.dims() || asItWas.originMm() != grid.originMm() ||
      asItWas.voxelSizeMm() != grid.voxelSizeMm()) {
    throw std::logic_error("SurfaceUpdater: the grid as it was has another shape than the grid");
  }
  SurfaceOptions check = options;
  check.method = SurfaceMethod::CrackFree;
  Impl& m = *impl_;
  m.grid = &asItWas;
  m.options = check;
  m.cellBricks = grid.brickDims() + 1;
  m.vs = grid.voxelSizeMm();
  m.bricks.resize(std::size_t(m.cellBricks.x) * std::size_t(m.cellBricks.y) *
                  std::size_t(m.cellBricks.z));
  m.buildAll();
  m.grid = &grid;
}

SurfaceUpdater::~SurfaceUpdater() = default;

SurfaceUpdater::UpdateStats SurfaceUpdater::update(
    const std::vector<std::size_t>& changedGridBricks) {
  const auto start = Clock::now();
  Impl& m = *impl_;
  UpdateStats stats;
  // Cells read voxels of their own grid brick and of the next one up on each axis, so a
  // changed brick G concerns cell bricks G - d, d in {0, 1}^3.
  std::vector<glm::ivec3> cells;
  for (const std::size_t g : changedGridBricks) {
    const glm::ivec3 gb = m.grid->brickCoord(g);
    for (int d = 0; d < 8; ++d) {
      const glm::ivec3 cb = gb - glm::ivec3(d & 1, (d >> 1) & 1, (d >> 2) & 1);
      if (m.validBrick(cb)) cells.push_back(cb);
    }
  }
  // In brick order, once each (no table the size of the grid's bricks for a few of them).
  const auto before = [&](const glm::ivec3& a, const glm::ivec3& b) {
    return m.brickIndex(a) < m.brickIndex(b);
  };
  std::sort(cells.begin(), cells.end(), before);
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<std::uint32_t> touched;
  // Edges first (triangles refer to vertices of neighbouring bricks), then triangles.
  for (const glm::ivec3& cb : cells) m.rebuildEdges(cb, touched);
  for (const glm::ivec3& cb : cells) m.rebuildTriangles(cb, touched);
  // A cell brick with no surface left gives its memory back.
  for (const glm::ivec3& cb : cells) {
    std::unique_ptr<Impl::CellBrick>& b = m.bricks[m.brickIndex(cb)];
    if (b && b->triangles.empty() && b->owned.count() == 0) {
      m.noteBrick(m.brickIndex(cb));
      b.reset();
    }
  }
  m.freeSlots.insert(m.freeSlots.end(), m.pendingFree.begin(), m.pendingFree.end());
  m.pendingFree.clear();
  stats.cellBricks = cells.size();
  stats.verticesTouched = touched.size();
  const auto smoothStart = Clock::now();
  stats.extractMs = std::chrono::duration<double, std::milli>(smoothStart - start).count();
  stats.verticesSmoothed = m.resmooth(touched);
  stats.smoothMs = msSince(smoothStart);
  stats.ms = msSince(start);
  return stats;
}

SurfaceMesh SurfaceUpdater::mesh() const {
  const Impl& m = *impl_;
  SurfaceMesh out;
  std::vector<std::uint32_t> index(m.info.size(), kNoVertex);
  for (std::size_t s = 0; s < m.info.size(); ++s) {
    if (!m.alive[s]) continue;
    index[s] = std::uint32_t(out.positionsMm.size());
    out.positionsMm.push_back(m.position[s]);
    out.normals.push_back(m.normal[s]);
  }
  for (std::size_t bi = 0; bi < m.bricks.size(); ++bi) {
    const Impl::CellBrick* b = m.bricks[bi].get();
    if (!b || b->triangles.empty()) continue;
    const auto first = std::uint32_t(out.triangles.size());
    for (const glm::u32vec3& t : b->triangles)
      out.triangles.push_back({index[t.x], index[t.y], index[t.z]});
    out.brickRanges.push_back(
        {std::int64_t(bi), m.cellBrickOf(bi), first, std::uint32_t(b->triangles.size())});
  }
  return out;
}

SurfaceDelta SurfaceUpdater::takeChanges() {
  Impl& m = *impl_;
  SurfaceDelta d;
  d.slotCount = m.info.size();
  d.everything = m.everything;
  std::vector<std::uint32_t> slots, bricks;
  if (m.everything) {
    for (std::uint32_t s = 0; s < m.info.size(); ++s) slots.push_back(s);
    for (std::size_t b = 0; b < m.bricks.size(); ++b) {
      if (m.bricks[b] && !m.bricks[b]->triangles.empty()) bricks.push_back(std::uint32_t(b));
    }
  } else {
    slots.swap(m.changedSlots);
    bricks.swap(m.changedBricks);
    std::sort(slots.begin(), slots.end());
    std::sort(bricks.begin(), bricks.end());
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const std::uint32_t s : slots) {
    d.slots.push_back(s);
    d.positionsMm.push_back(m.alive[s] ? m.position[s] : glm::dvec3(nan));
    d.normals.push_back(m.alive[s] ? m.normal[s] : glm::dvec3(nan));
  }
  for (const std::uint32_t b : bricks) {
    const Impl::CellBrick* brick = m.bricks[b].get();
    d.bricks.push_back({std::int64_t(b), brick ? brick->triangles : std::vector<glm::u32vec3>{}});
  }
  m.everything = false;
  m.slotChanged.assign(m.info.size(), 0);
  m.brickChanged.assign(m.bricks.size(), 0);
  m.changedSlots.clear();
  m.changedBricks.clear();
  return d;
}

std::string SurfaceUpdater::validate() const {
  const Impl& m = *impl_;
  for (std::size_t bi = 0; bi < m.bricks.size(); ++bi) {
    const Impl::CellBrick* b = m.bricks[bi].get();
    if (!b) continue;
    for (std::size_t k = 0; k < b->triangles.size(); ++k) {
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = b->triangles[k][c];
        if (v >= m.alive.size() || !m.alive[v]) {
          return "cell brick " + std::to_string(bi) + " triangle " + std::to_string(k) +
                 " uses freed vertex slot " + std::to_string(v);
        }
      }
    }
    for (std::uint32_t v : b->owned.slots()) {
      if (v >= m.alive.size() || !m.alive[v])
        return "cell brick " + std::to_string(bi) + " owns a freed slot";
    }
  }
  return "";
}

std::size_t SurfaceUpdater::vertexCount() const {
  std::size_t n = 0;
  for (std::size_t s = 0; s < impl_->alive.size(); ++s) n += impl_->alive[s];
  return n;
}

std::size_t SurfaceUpdater::triangleCount() const {
  std::size_t n = 0;
  for (const auto& b : impl_->bricks) n += b ? b->triangles.size() : 0;
  return n;
}

SurfaceUpdater::Memory SurfaceUpdater::memory() const {
  return impl_->memory();
}

SurfaceUpdater::Memory SurfaceUpdater::Impl::memory() const {
  Memory out;
  for (const auto& b : bricks) {
    if (!b) continue;
    out.cellBricks += b->memoryBytes() - b->triangles.capacity() * sizeof(glm::u32vec3);
    out.triangles += b->triangles.capacity() * sizeof(glm::u32vec3);
  }
  out.vertices = info.memoryBytes() + position.memoryBytes() + normal.memoryBytes() +
                 alive.memoryBytes() + mark.memoryBytes() + local.memoryBytes() +
                 slotChanged.memoryBytes();
  out.loops = loops.memoryBytes();
  out.tables = bricks.capacity() * sizeof(bricks[0]) +
               (freeSlots.capacity() + pendingFree.capacity() + freeLoops.capacity() +
                changedSlots.capacity() + changedBricks.capacity() + region.capacity() +
                rowStart.capacity() + rows.capacity() + nb.capacity()) *
                   sizeof(std::uint32_t) +
               brickChanged.capacity() + oldTriangles.capacity() * sizeof(glm::u32vec3) +
               depthOf.capacity() * sizeof(int) + cur.capacity() * sizeof(glm::dvec3) +
               (curT.capacity() + nextT.capacity()) * sizeof(double);
  return out;
}

std::size_t SurfaceUpdater::Impl::resmooth(const std::vector<std::uint32_t>& touched) {
  const int passes = options.smoothIterations;
  const int keep = passes;
  const int reach = std::max(2 * passes - 1, passes);
  ++epoch;
  region.clear();
  depthOf.clear();
  for (std::uint32_t v : touched) {
    if (!alive[v] || mark[v] == epoch) continue;
    mark[v] = epoch;
    local[v] = std::uint32_t(region.size());
    region.push_back(v);
    depthOf.push_back(0);
  }
  rowStart.assign(1, 0);
  rows.clear();
  for (std::size_t i = 0; i < region.size(); ++i) {
    neighbours(region[i], nb);
    rows.insert(rows.end(), nb.begin(), nb.end());
    rowStart.push_back(std::uint32_t(rows.size()));
    if (depthOf[i] >= reach) continue;
    for (std::uint32_t n : nb) {
      const auto visit = [&](std::uint32_t w) {
        if (mark[w] == epoch) return;
        mark[w] = epoch;
        local[w] = std::uint32_t(region.size());
        region.push_back(w);
        depthOf.push_back(depthOf[i] + 1);
      };
      visit(n);
      if (info[n].axis == 3) {
        const std::uint32_t* l = loopOf(info[n]);
        for (int k = 0; k < info[n].loopSize; ++k) visit(l[k]);
      }
    }
  }
  const auto raw = [&](std::uint32_t slot) { return rawPosition(slot); };
  const std::size_t n = region.size();
  cur.resize(n);
  curT.resize(n);
  nextT.resize(n);
  const auto now = [&](std::uint32_t slot) {
    return mark[slot] == epoch ? cur[local[slot]] : raw(slot);
  };
  for (std::size_t i = 0; i < n; ++i) {
    curT[i] = info[region[i]].axis == 3 ? 0.0 : info[region[i]].t;
    cur[i] = raw(region[i]);
  }
  for (int pass = 0; pass < passes; ++pass) {
    const double step = options.taubin && pass % 2 == 1 ? options.mu : options.lambda;
    for (std::size_t i = 0; i < n; ++i) {
      const SlotInfo& v = info[region[i]];
      if (v.axis == 3) continue;
      double mean = 0.0;
      for (std::uint32_t k = rowStart[i]; k < rowStart[i + 1]; ++k) mean += now(rows[k])[v.axis];
      mean /= double(rowStart[i + 1] - rowStart[i]);
      nextT[i] =
          std::clamp(curT[i] + step * (mean - cur[i][v.axis]) / vs, kEdgeMargin, 1.0 - kEdgeMargin);
    }
    for (std::size_t i = 0; i < n; ++i) {
      SlotInfo v = info[region[i]];
      if (v.axis == 3) continue;
      curT[i] = nextT[i];
      v.t = curT[i];
      cur[i] = edgePosition(v);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t slot = region[i];
      const SlotInfo& c = info[slot];
      if (c.axis != 3) continue;
      glm::dvec3 sum(0.0);
      const std::uint32_t* l = loopOf(c);
      for (int k = 0; k < c.loopSize; ++k) sum += now(l[k]);
      cur[i] = sum / double(c.loopSize);
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (depthOf[i] <= keep) {
      position[region[i]] = cur[i];
      noteSlot(region[i]);
      ++kept;
    }
  }
  // Normals of every kept vertex and its neighbours, from the triangles around them.
  for (std::size_t i = 0; i < n; ++i) {
    if (depthOf[i] > keep + 1) continue;
    const std::uint32_t v = region[i];
    glm::dvec3 sum(0.0);
    forEachIncident(v, [&](const glm::u32vec3& t) {
      sum += glm::cross(position[t.y] - position[t.x], position[t.z] - position[t.x]);
    });
    const double len = glm::length(sum);
    normal[v] = len > 0.0 ? sum / len : glm::dvec3(0.0);
    noteSlot(v);
  }
  return kept;
}

}  // namespace osteon::geometry
