#include "hierarchy_view.h"

#include <algorithm>
#include <chrono>

#include "osteon/core/timing.h"

namespace osteon::viewer {

namespace geo = osteon::geometry;

void appendBoxEdges(std::vector<glm::vec3>& points, const glm::vec3& lo, const glm::vec3& hi) {
  const auto corner = [&](int i) {
    return glm::vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  };
  for (int i = 0; i < 8; ++i) {
    for (const int bit : {1, 2, 4}) {
      if (!(i & bit)) {
        points.push_back(corner(i));
        points.push_back(corner(i | bit));
      }
    }
  }
}

DphBoxes computeDphBoxes(const geo::DynamicProximityHierarchy& h) {
  DphBoxes out;
  out.voxelMm = h.voxelSizeMm();
  out.originMm = h.voxelCentreMm(glm::ivec3(0)) - 0.5 * h.voxelSizeMm();
  const int levels = h.levelCount();
  // Per level, per node slot: its box (hi < lo for a dead node).
  std::vector<std::vector<DphBoxes::Box>> slots(std::size_t(std::max(levels, 0)));
  for (int level = 0; level < levels; ++level) {
    std::vector<DphBoxes::Box>& mine = slots[std::size_t(level)];
    mine.assign(h.nodeSlots(level), DphBoxes::Box{glm::ivec3(1), glm::ivec3(0)});
    for (std::uint32_t n = 0; n < h.nodeSlots(level); ++n) {
      if (!h.alive(level, n)) continue;
      if (level == 0) {
        mine[n] = {h.centre(0, n), h.centre(0, n)};
        continue;
      }
      DphBoxes::Box box{glm::ivec3(1), glm::ivec3(0)};
      bool any = false;
      const std::vector<DphBoxes::Box>& below = slots[std::size_t(level - 1)];
      for (std::uint32_t c = h.childBegin(level, n); c < h.childEnd(level, n); ++c) {
        if (!h.alive(level - 1, c)) continue;
        const DphBoxes::Box& b = below[c];
        box.lo = any ? glm::min(box.lo, b.lo) : b.lo;
        box.hi = any ? glm::max(box.hi, b.hi) : b.hi;
        any = true;
      }
      if (any) mine[n] = box;
    }
  }
  out.levels.resize(slots.size());
  for (std::size_t level = 0; level < slots.size(); ++level) {
    for (const DphBoxes::Box& b : slots[level]) {
      if (glm::all(glm::lessThanEqual(b.lo, b.hi))) out.levels[level].push_back(b);
    }
  }
  out.voxels = h.voxelCount();
  return out;
}

void HierarchyView::maybeRebuild(const geo::VoxelGrid& grid, double nowS, bool force) {
  if (building() || (!force && nowS - lastStartS_ < kRebuildEveryS)) return;
  lastStartS_ = nowS;
  // The occupied voxels, read here (the grid changes on this thread between frames).
  std::vector<glm::ivec3> voxels;
  const glm::ivec3 dims = grid.dims();
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    const bool allocated = grid.brickAllocated(brick);
    if (!allocated && grid.brickUniformFill(brick) == 0) continue;
    const glm::ivec3 lo = grid.brickCoord(brick) * geo::VoxelGrid::kBrickSize;
    const glm::ivec3 hi = glm::min(lo + geo::VoxelGrid::kBrickSize, dims);
    for (int z = lo.z; z < hi.z; ++z) {
      for (int y = lo.y; y < hi.y; ++y) {
        for (int x = lo.x; x < hi.x; ++x) {
          if (!allocated || grid.fill({x, y, z}) > 0) voxels.emplace_back(x, y, z);
        }
      }
    }
  }
  const glm::dvec3 origin = grid.originMm();
  const double voxelMm = grid.voxelSizeMm();
  pending_ = std::async(std::launch::async, [voxels = std::move(voxels), origin, voxelMm] {
    const Clock::time_point start = Clock::now();
    const geo::DynamicProximityHierarchy h =
        geo::DynamicProximityHierarchy::build(voxels, geo::DphBuildOptions{}, origin, voxelMm);
    auto boxes = std::make_unique<DphBoxes>(computeDphBoxes(h));
    boxes->buildMs = msSince(start);
    return boxes;
  });
}

void HierarchyView::poll() {
  if (!pending_.valid() || pending_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    return;
  boxes_ = pending_.get();
}

void HierarchyView::clear() {
  if (pending_.valid()) pending_.wait();
  pending_ = {};
  boxes_.reset();
  lastStartS_ = -1e9;
}

std::size_t HierarchyView::linesAround(int level, const glm::dvec3& pointMm, double radiusMm,
                                       std::size_t maxBoxes, std::vector<glm::vec3>& points) const {
  if (!boxes_ || level < 0 || level >= levelCount()) return 0;
  const DphBoxes& b = *boxes_;
  std::size_t drawn = 0;
  for (const DphBoxes::Box& box : b.levels[std::size_t(level)]) {
    if (drawn >= maxBoxes) break;
    // The box's extent in mm: voxel lo's corner to voxel hi's far corner.
    const glm::dvec3 lo = b.originMm + glm::dvec3(box.lo) * b.voxelMm;
    const glm::dvec3 hi = b.originMm + (glm::dvec3(box.hi) + 1.0) * b.voxelMm;
    const glm::dvec3 nearest = glm::clamp(pointMm, lo, hi);
    if (glm::length(nearest - pointMm) > radiusMm) continue;
    appendBoxEdges(points, glm::vec3(lo), glm::vec3(hi));
    ++drawn;
  }
  return drawn;
}

}  // namespace osteon::viewer
