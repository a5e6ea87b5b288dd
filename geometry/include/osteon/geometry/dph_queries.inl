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

// One axis of a sphere query in grid space: the integers lo .. lo + size - 1 around the
// centre's coordinate g, one beyond the radius on each side, with their squared distances
// (i - g)^2 computed as the plain test computes them. An integer outside the window is more
// than r + 1 from g, so no rounding can put it in reach: rejecting it by compare is exact.
struct AxisWindow {
  static constexpr int kMaxSize = 64;
  int lo = 0;
  unsigned size = 0;
  double sq[kMaxSize];
  // False when the window would not fit (a large radius, or a point far off the grid).
  bool build(double g, double r) {
    if (!(std::abs(g) < 1e9) || !(r >= 0.0) || !(r < 0.5 * kMaxSize - 2.0)) return false;
    lo = int(std::floor(g - r)) - 1;
    const int hi = int(std::ceil(g + r)) + 1;
    size = unsigned(hi - lo + 1);
    for (unsigned i = 0; i < size; ++i) {
      const double d = double(lo + int(i)) - g;
      sq[i] = d * d;
    }
    gridPoint = g;
    return true;
  }
  bool overlaps(int boxLo, int boxHi) const { return boxHi >= lo && boxLo < lo + int(size); }
  // max(boxLo - g, g - boxHi, 0)^2 for a box that overlaps the window.
  double boxSq(int boxLo, int boxHi) const {
    if (double(boxLo) > gridPoint) return sq[boxLo - lo];
    if (double(boxHi) < gridPoint) return sq[boxHi - lo];
    return 0.0;
  }
  double gridPoint = 0.0;
};

// The sphere query's leaf test from the three windows: (x^2 + y^2) + z^2 <= r2, as glm::dot.
inline bool inWindows(const AxisWindow (&w)[3], const glm::ivec3& v, double r2) {
  const auto ix = unsigned(v.x - w[0].lo), iy = unsigned(v.y - w[1].lo), iz = unsigned(v.z - w[2].lo);
  if (ix >= w[0].size || iy >= w[1].size || iz >= w[2].size) return false;
  return w[0].sq[ix] + w[1].sq[iy] + w[2].sq[iz] <= r2;
}

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
      leaf(lv.centre[node], node);
      continue;
    }
    if (!reach(level, node)) continue;
    const Level& below = levels_[std::size_t(level) - 1];
    if (level == 1) {  // voxels straight to `leaf`, not through the stack (most of the work)
      for (std::uint32_t c = lv.childBegin[node]; c < lv.childEnd[node]; ++c) {
        if (below.alive[c]) leaf(below.centre[c], c);
      }
      continue;
    }
    for (std::uint32_t c = lv.childBegin[node]; c < lv.childEnd[node]; ++c) {
      if (below.alive[c]) stack[top++] = dph_detail::packItem(level - 1, c);
    }
  }
}

template <typename Walk, typename Test, typename Fn>
void DynamicProximityHierarchy::answerThroughCache(const glm::dvec3& a, const glm::dvec3& b, double radiusMm,
                                                   DphNearCache& cache, Walk&& walk, Test&& test,
                                                   Fn&& fn) const {
  if (cache.covers(*this, a, b, radiusMm)) {
    ++cache.reuses_;
  } else {
    ++cache.walks_;
    cache.reachMm_ = -1.0;
    cache.nodes_.clear();
    cache.centres_.clear();
    bool fits = true;
    walk(radiusMm + cache.skinMm_, [&](const glm::ivec3& v, std::uint32_t node) {
      if (cache.nodes_.size() == cache.nodes_.capacity()) {
        fits = false;
        return;
      }
      cache.nodes_.push_back(node);
      cache.centres_.push_back(v);
    });
    if (!fits) {
      ++cache.overflows_;
      walk(radiusMm, [&](const glm::ivec3& v, std::uint32_t) { fn(v); });
      return;
    }
    cache.owner_ = this;
    cache.generation_ = generation_;
    cache.aMm_ = a;
    cache.bMm_ = b;
    cache.reachMm_ = radiusMm + cache.skinMm_;
  }
  const std::uint8_t* alive = levels_[0].alive.data();
  const std::size_t n = cache.nodes_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::ivec3& v = cache.centres_[i];
    if (alive[cache.nodes_[i]] && test(v)) fn(v);
  }
}

template <typename Fn>
void DynamicProximityHierarchy::forEachVoxelInSphere(const glm::dvec3& centreMm, double radiusMm,
                                                     DphQueryScratch& scratch, DphNearCache* cache,
                                                     Fn&& fn) const {
  const glm::dvec3 g = (centreMm - originMm_) / voxelSizeMm_ - 0.5;
  // Walks the hierarchy for the voxels within radius of the centre: leaf(centre, node).
  const auto walk = [&](double radius, auto&& leaf) {
    const double r = radius / voxelSizeMm_;
    const double r2 = r * r;
    dph_detail::AxisWindow w[3];
    if (w[0].build(g.x, r) && w[1].build(g.y, r) && w[2].build(g.z, r)) {
      // Most nodes a step's query meets are out of reach by a whole axis: rejected by integer
      // compares against the window, the rest summed from the windows' squares (the same
      // values, in the same order, as the plain test below).
      const auto reach = [&](int level, std::uint32_t node) {
        const Level& lv = levels_[std::size_t(level)];
        const glm::ivec3& lo = lv.boxMin[node];
        const glm::ivec3& hi = lv.boxMax[node];
        if (!w[0].overlaps(lo.x, hi.x) || !w[1].overlaps(lo.y, hi.y) || !w[2].overlaps(lo.z, hi.z)) return false;
        return w[0].boxSq(lo.x, hi.x) + w[1].boxSq(lo.y, hi.y) + w[2].boxSq(lo.z, hi.z) <= r2;
      };
      traverse(scratch, reach, [&](const glm::ivec3& v, std::uint32_t node) {
        if (dph_detail::inWindows(w, v, r2)) leaf(v, node);
      });
      return;
    }
    const auto reach = [&](int level, std::uint32_t node) {
      return boxDistanceSq(level, node, g) <= r2;
    };
    traverse(scratch, reach, [&](const glm::ivec3& v, std::uint32_t node) {
      const glm::dvec3 d = glm::dvec3(v) - g;
      if (glm::dot(d, d) <= r2) leaf(v, node);
    });
  };
  if (!cache) {
    walk(radiusMm, [&](const glm::ivec3& v, std::uint32_t) { fn(v); });
    return;
  }
  // The walk's leaf test at the query's radius, for the kept voxels.
  const double r = radiusMm / voxelSizeMm_;
  const double r2 = r * r;
  dph_detail::AxisWindow w[3];
  const bool windowed = w[0].build(g.x, r) && w[1].build(g.y, r) && w[2].build(g.z, r);
  const auto test = [&](const glm::ivec3& v) {
    if (windowed) return dph_detail::inWindows(w, v, r2);
    const glm::dvec3 d = glm::dvec3(v) - g;
    return glm::dot(d, d) <= r2;
  };
  answerThroughCache(centreMm, centreMm, radiusMm, *cache, walk, test, fn);
}

template <typename Fn>
void DynamicProximityHierarchy::forEachVoxelInCapsule(const glm::dvec3& aMm, const glm::dvec3& bMm,
                                                      double radiusMm, DphQueryScratch& scratch,
                                                      DphNearCache* cache, Fn&& fn) const {
  const glm::dvec3 a = (aMm - originMm_) / voxelSizeMm_ - 0.5;
  const glm::dvec3 b = (bMm - originMm_) / voxelSizeMm_ - 0.5;
  const dph_detail::Segment segment(a, b);
  const auto walk = [&](double radius, auto&& leaf) {
    const double r = radius / voxelSizeMm_;
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
    traverse(scratch, reach, [&](const glm::ivec3& v, std::uint32_t node) {
      if (segment.distanceSq(glm::dvec3(v)) <= r2) leaf(v, node);
    });
  };
  if (!cache) {
    walk(radiusMm, [&](const glm::ivec3& v, std::uint32_t) { fn(v); });
    return;
  }
  const double r = radiusMm / voxelSizeMm_;
  const double r2 = r * r;
  answerThroughCache(aMm, bMm, radiusMm, *cache, walk,
                     [&](const glm::ivec3& v) { return segment.distanceSq(glm::dvec3(v)) <= r2; }, fn);
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
  const auto leaf = [&](const glm::ivec3& v, std::uint32_t) {
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
