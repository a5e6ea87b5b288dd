// The hierarchy view's data: a Dynamic Proximity Hierarchy of the viewer's own, built from the
// visual grid when the view is entered and every few seconds while it is shown (off the render
// thread), reduced to each alive node's box of level-0 descendant voxels per level. The boxes
// come from the public API (child ranges and centres), bottom-up, so they are the boxes the
// hierarchy's queries prune with as long as those stay tight.
#pragma once

#include <cstddef>
#include <future>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::viewer {

struct DphBoxes {
  struct Box {
    glm::ivec3 lo, hi;  // voxel indices, inclusive
  };
  std::vector<std::vector<Box>> levels;  // alive nodes per level (level 0: single voxels)
  glm::dvec3 originMm{0.0};
  double voxelMm = 1.0;
  double buildMs = 0.0;  // hierarchy and boxes
  std::size_t voxels = 0;
};

// Every alive node's box of level-0 descendants, level by level.
DphBoxes computeDphBoxes(const geometry::DynamicProximityHierarchy& hierarchy);

// The 12 edges of an axis-aligned box, appended as 24 points.
void appendBoxEdges(std::vector<glm::vec3>& points, const glm::vec3& lo, const glm::vec3& hi);

class HierarchyView {
 public:
  static constexpr double kRebuildEveryS = 2.0;

  // Starts a build from the grid's occupied voxels when none is running and the last started
  // kRebuildEveryS ago or more (or `force`). Reads the grid now, on the calling thread.
  void maybeRebuild(const geometry::VoxelGrid& grid, double nowS, bool force);
  // Takes a finished build, if any. Throws what the build threw.
  void poll();
  void clear();

  bool ready() const { return boxes_ != nullptr; }
  bool building() const { return pending_.valid(); }
  int levelCount() const { return boxes_ ? int(boxes_->levels.size()) : 0; }
  const DphBoxes* boxes() const { return boxes_.get(); }
  // The boxes of `level` within radiusMm of pointMm as line segments (mm), at most maxBoxes
  // of them (the nearest first is not promised). Returns how many boxes were drawn.
  std::size_t linesAround(int level, const glm::dvec3& pointMm, double radiusMm,
                          std::size_t maxBoxes, std::vector<glm::vec3>& points) const;

 private:
  std::unique_ptr<DphBoxes> boxes_;
  std::future<std::unique_ptr<DphBoxes>> pending_;
  double lastStartS_ = -1e9;
};

}  // namespace osteon::viewer
