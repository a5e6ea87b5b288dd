// Template bodies of DynamicProximityHierarchy's queries (included by dph.h).
#pragma once

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace osteon::geometry {

namespace dph_detail {

inline std::uint64_t packItem(int level, std::uint32_t node) {
  return (std::uint64_t(level) << 32) | node;
}

// Squared distance from a point to the segment a-b, the segment's terms computed once (no
// division per point).
struct Segment {
  glm::dvec3 a, ab;
  double len2, invLen2;
  Segment(const glm::dvec3& from, const glm::dvec3& to)
      : a(from), ab(to - from), len2(glm::dot(ab, ab)), invLen2(len2 > 0.0 ? 1.0 / len2 : 0.0) {}
  double distanceSq(const glm::dvec3& p) const {
    const glm::dvec3 ap = p - a;
    double t = glm::dot(ap, ab) * invLen2;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    const glm::dvec3 d = ap - t * ab;
    return glm::dot(d, d);
  }
};

}  // namespace dph_detail

// Inline: queried for every node a haptic step's queries visit.
inline double DynamicProximityHierarchy::boxDistanceSq(int level, std::uint32_t node, const glm::dvec3& g) const {
  const Level& lv = levels_[std::size_t(level)];
  const glm::dvec3 lo(lv.boxMin[node]);
  const glm::dvec3 hi(lv.boxMax[node]);
  const glm::dvec3 d = glm::max(glm::max(lo - g, g - hi), glm::dvec3(0.0));
  return glm::dot(d, d);
}

// Depth first from the root, visiting a node only when `reach(level, node)` says its subtree
// may hold an answer, and handing level-0 voxels to `leaf(centre)`. Grid space here puts
// voxel v's centre at v.
template <typename Reach, typename Leaf>
void DynamicProximityHierarchy::traverse(DphQueryScratch& scratch, Reach&& reach,
                                         Leaf&& leaf) const {
  const std::uint32_t rootNode = root();
  if (rootNode == kNone) return;
  reserveScratch(scratch);
  std::uint64_t* stack = scratch.stack.data();
  std::size_t top = 0;
  stack[top++] = dph_detail::packItem(levelCount() - 1, rootNode);
  while (top > 0) {
    const std::uint64_t item = stack[--top];
    const int level = int(item >> 32);
    const auto node = std::uint32_t(item & 0xffffffffu);
    const Level& lv = levels_[std::size_t(level)];
    if (level == 0) {
      leaf(lv.centre[node]);
      continue;
    }
    if (!reach(level, node)) continue;
    const Level& below = levels_[std::size_t(level) - 1];
    if (level == 1) {  // voxels straight to `leaf`, not through the stack (most of the work)
      for (std::uint32_t c = lv.childBegin[node]; c < lv.childEnd[node]; ++c) {
        if (below.alive[c]) leaf(below.centre[c]);
      }
      continue;
    }
    for (std::uint32_t c = lv.childBegin[node]; c < lv.childEnd[node]; ++c) {
      if (below.alive[c]) stack[top++] = dph_detail::packItem(level - 1, c);
    }
  }
}

template <typename Fn>
void DynamicProximityHierarchy::forEachVoxelInSphere(const glm::dvec3& centreMm, double radiusMm,
                                                     DphQueryScratch& scratch, Fn&& fn) const {
  const glm::dvec3 g = (centreMm - originMm_) / voxelSizeMm_ - 0.5;
  const double r = radiusMm / voxelSizeMm_;
  const double r2 = r * r;
  const auto reach = [&](int level, std::uint32_t node) {
    return boxDistanceSq(level, node, g) <= r2;
  };
  const auto leaf = [&](const glm::ivec3& v) {
    const glm::dvec3 d = glm::dvec3(v) - g;
    if (glm::dot(d, d) <= r2) fn(v);
  };
  traverse(scratch, reach, leaf);
}

template <typename Fn>
void DynamicProximityHierarchy::forEachVoxelInCapsule(const glm::dvec3& aMm, const glm::dvec3& bMm,
                                                      double radiusMm, DphQueryScratch& scratch,
                                                      Fn&& fn) const {
  const glm::dvec3 a = (aMm - originMm_) / voxelSizeMm_ - 0.5;
  const glm::dvec3 b = (bMm - originMm_) / voxelSizeMm_ - 0.5;
  const double r = radiusMm / voxelSizeMm_;
  const dph_detail::Segment segment(a, b);
  const auto reach = [&](int level, std::uint32_t node) {
    // The box's circumscribed sphere against the segment: a safe lower bound.
    const Level& lv = levels_[std::size_t(level)];
    const glm::dvec3 lo(lv.boxMin[node]);
    const glm::dvec3 hi(lv.boxMax[node]);
    const glm::dvec3 mid = 0.5 * (lo + hi);
    const double halfDiagonal = 0.5 * glm::length(hi - lo);
    const double d = std::sqrt(segment.distanceSq(mid)) - halfDiagonal;
    return d <= r;
  };
  const double r2 = r * r;
  const auto leaf = [&](const glm::ivec3& v) {
    if (segment.distanceSq(glm::dvec3(v)) <= r2) fn(v);
  };
  traverse(scratch, reach, leaf);
}

inline bool DynamicProximityHierarchy::nearestVoxel(const glm::dvec3& pointMm,
                                                    DphQueryScratch& scratch, glm::ivec3& voxel,
                                                    double& distanceMm) const {
  const glm::dvec3 g = (pointMm - originMm_) / voxelSizeMm_ - 0.5;
  double best = std::numeric_limits<double>::infinity();
  bool found = false;
  const auto reach = [&](int level, std::uint32_t node) {
    return boxDistanceSq(level, node, g) < best;
  };
  const auto leaf = [&](const glm::ivec3& v) {
    const glm::dvec3 d = glm::dvec3(v) - g;
    const double d2 = glm::dot(d, d);
    if (d2 < best) {
      best = d2;
      voxel = v;
      found = true;
    }
  };
  traverse(scratch, reach, leaf);
  if (found) distanceMm = std::sqrt(best) * voxelSizeMm_;
  return found;
}

}  // namespace osteon::geometry
