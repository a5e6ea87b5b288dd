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
// may hold an answer, and handing level-0 voxels to `leaf(centre, node)`. Grid space here puts
// voxel v's centre at v.
template <typename Reach, typename Leaf>
void DynamicProximityHierarchy::traverse(DphQueryScratch& scratch, Reach&& reach,
                                         Leaf&& leaf) const {
  reserveScratch(scratch);
  std::size_t top = 0;
  startTraversal(scratch.stack.data(), top);
  traverseFrom(scratch.stack.data(), top, std::numeric_limits<std::size_t>::max(), reach, leaf);
}

inline void DynamicProximityHierarchy::startTraversal(std::uint64_t* stack, std::size_t& top) const {
  top = 0;
  const std::uint32_t rootNode = root();
  if (rootNode != kNone) stack[top++] = dph_detail::packItem(levelCount() - 1, rootNode);
}

// Removals between two calls only clear alive flags: a saved stack stays valid, and a voxel
// handed to `leaf` may since have gone (callers check alive() when they use it).
template <typename Reach, typename Leaf>
bool DynamicProximityHierarchy::traverseFrom(std::uint64_t* stack, std::size_t& top, std::size_t budget,
                                             Reach&& reach, Leaf&& leaf) const {
  std::size_t spent = 0;
  while (top > 0) {
    if (spent >= budget) return false;
    const std::uint64_t item = stack[--top];
    const int level = int(item >> 32);
    const auto node = std::uint32_t(item & 0xffffffffu);
    const Level& lv = levels_[std::size_t(level)];
    ++spent;
    if (level == 0) {  // the root of a one-voxel hierarchy (its centre is kept)
      leaf(lv.centre[node], node);
      continue;
    }
    if (!reach(level, node)) continue;
    const Level& below = levels_[std::size_t(level) - 1];
    const std::uint32_t begin = lv.childBegin[node], end = lv.childEnd[node];
    spent += end - begin;
    if (level == 1) {  // voxels straight to `leaf`, not through the stack (most of the work)
      if (below.digit.empty()) {
        for (std::uint32_t c = begin; c < end; ++c) {
          if (below.alive[c]) leaf(below.centre[c], c);
        }
      } else {
        const glm::ivec3 corner = lv.centre[node] - int(halfWidth_[1]);
        for (std::uint32_t c = begin; c < end; ++c) {
          if (below.alive[c]) leaf(corner + digitOffset_[below.digit[c]], c);
        }
      }
      continue;
    }
    for (std::uint32_t c = begin; c < end; ++c) {
      if (below.alive[c]) stack[top++] = dph_detail::packItem(level - 1, c);
    }
  }
  return true;
}

template <typename WalkFrom, typename Leaf>
void DynamicProximityHierarchy::walkWhole(DphQueryScratch& scratch, WalkFrom&& walkFrom, const glm::dvec3& a,
                                          const glm::dvec3& b, double radiusMm, Leaf&& leaf) const {
  reserveScratch(scratch);
  std::size_t top = 0;
  startTraversal(scratch.stack.data(), top);
  walkFrom(a, b, radiusMm, scratch.stack.data(), top, std::numeric_limits<std::size_t>::max(), leaf);
}

template <typename WalkFrom, typename Test, typename Fn>
void DynamicProximityHierarchy::answerThroughCache(int kind, const glm::dvec3& a, const glm::dvec3& b,
                                                   double radiusMm, DphQueryScratch& scratch,
                                                   DphNearCache& cache, WalkFrom&& walkFrom, Test&& test,
                                                   Fn&& fn) const {
  using Answer = DphNearCache::Answer;
  cache.recordTravel(a, b);  // the odometer first: a query's travel counts before its answer
  if (cache.owner_ != this || cache.generation_ != generation_) {
    cache.clear();
    cache.owner_ = this;
    cache.generation_ = generation_;
  }
  const auto walkNow = [&](double radius, auto&& leaf) { walkWhole(scratch, walkFrom, a, b, radius, leaf); };
  // A complete next answer takes over when it covers the query.
  if (!cache.slicing_ && cache.next_.reachMm >= 0.0) {
    if (cache.nextFits_ && cache.nextKind_ == kind && cache.covers(*this, cache.next_, a, b, radiusMm)) {
      std::swap(cache.kept_, cache.next_);
      ++cache.sliced_;
    }
    cache.next_.reachMm = -1.0;
  }
  Answer& kept = cache.kept_;
  if (cache.covers(*this, kept, a, b, radiusMm)) {
    ++cache.reuses_;
  } else {
    ++cache.walks_;
    cache.slicing_ = false;
    cache.next_.reachMm = -1.0;
    kept.reachMm = -1.0;
    kept.nodes.clear();
    kept.centres.clear();
    bool fits = true;
    walkNow(radiusMm + cache.skinMm_, [&](const glm::ivec3& v, std::uint32_t node) { fits = kept.add(v, node) && fits; });
    if (!fits) {
      ++cache.overflows_;
      kept.nodes.clear();
      kept.centres.clear();
      walkNow(radiusMm, [&](const glm::ivec3& v, std::uint32_t) { fn(v); });
      return;
    }
    kept.aMm = a;
    kept.bMm = b;
    kept.reachMm = radiusMm + cache.skinMm_;
  }
  const std::uint8_t* alive = levels_[0].alive.data();
  const std::size_t n = kept.nodes.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::ivec3& v = kept.centres[i];
    if (alive[kept.nodes[i]] && test(v)) fn(v);
  }
  // The next answer, a slice per query, once a third of the skin is used.
  if (cache.sliceNodes_ == 0 || cache.stack_.size() < traversalStackSize()) return;
  Answer& next = cache.next_;
  if (cache.slicing_ && cache.nextKind_ != kind) {  // gathered for another kind of query
    cache.slicing_ = false;
    next.reachMm = -1.0;
  }
  if (!cache.slicing_ && next.reachMm < 0.0 && DphNearCache::moved(kept, a, b) > cache.skinMm_ / 3.0) {
    cache.nextKind_ = kind;
    next.nodes.clear();
    next.centres.clear();
    next.aMm = a;
    next.bMm = b;
    next.reachMm = radiusMm + cache.skinMm_;
    cache.nextFits_ = true;
    cache.slicing_ = true;
    startTraversal(cache.stack_.data(), cache.top_);
  }
  if (cache.slicing_) {
    cache.slicing_ = !walkFrom(next.aMm, next.bMm, next.reachMm, cache.stack_.data(), cache.top_, cache.sliceNodes_,
                               [&](const glm::ivec3& v, std::uint32_t node) {
                                 cache.nextFits_ = next.add(v, node) && cache.nextFits_;
                               });
    if (!cache.slicing_ && !cache.nextFits_) ++cache.overflows_;
  }
}

template <typename Fn>
void DynamicProximityHierarchy::forEachVoxelInSphere(const glm::dvec3& centreMm, double radiusMm,
                                                     DphQueryScratch& scratch, DphNearCache* cache,
                                                     Fn&& fn) const {
  if (root() == kNone) return;  // no voxel (an empty grid, or every voxel removed)
  // Walks for the voxels within radius of a centre, from a saved stack: leaf(centre, node).
  const auto walkFrom = [&](const glm::dvec3& cMm, const glm::dvec3&, double radius, std::uint64_t* stack,
                            std::size_t& top, std::size_t budget, auto&& leaf) {
    const glm::dvec3 g = (cMm - originMm_) / voxelSizeMm_ - 0.5;
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
      return traverseFrom(stack, top, budget, reach, [&](const glm::ivec3& v, std::uint32_t node) {
        if (dph_detail::inWindows(w, v, r2)) leaf(v, node);
      });
    }
    const auto reach = [&](int level, std::uint32_t node) {
      return boxDistanceSq(level, node, g) <= r2;
    };
    return traverseFrom(stack, top, budget, reach, [&](const glm::ivec3& v, std::uint32_t node) {
      const glm::dvec3 d = glm::dvec3(v) - g;
      if (glm::dot(d, d) <= r2) leaf(v, node);
    });
  };
  if (!cache) {
    walkWhole(scratch, walkFrom, centreMm, centreMm, radiusMm, [&](const glm::ivec3& v, std::uint32_t) { fn(v); });
    return;
  }
  // The walk's leaf test at the query's radius, for the kept voxels.
  const glm::dvec3 g = (centreMm - originMm_) / voxelSizeMm_ - 0.5;
  const double r = radiusMm / voxelSizeMm_;
  const double r2 = r * r;
  dph_detail::AxisWindow w[3];
  const bool windowed = w[0].build(g.x, r) && w[1].build(g.y, r) && w[2].build(g.z, r);
  const auto test = [&](const glm::ivec3& v) {
    if (windowed) return dph_detail::inWindows(w, v, r2);
    const glm::dvec3 d = glm::dvec3(v) - g;
    return glm::dot(d, d) <= r2;
  };
  answerThroughCache(1, centreMm, centreMm, radiusMm, scratch, *cache, walkFrom, test, fn);
}

template <typename Fn>
void DynamicProximityHierarchy::forEachVoxelInCapsule(const glm::dvec3& aMm, const glm::dvec3& bMm,
                                                      double radiusMm, DphQueryScratch& scratch,
                                                      DphNearCache* cache, Fn&& fn) const {
  if (root() == kNone) return;  // no voxel (an empty grid, or every voxel removed)
  const auto walkFrom = [&](const glm::dvec3& fromMm, const glm::dvec3& toMm, double radius, std::uint64_t* stack,
                            std::size_t& top, std::size_t budget, auto&& leaf) {
    const dph_detail::Segment segment((fromMm - originMm_) / voxelSizeMm_ - 0.5, (toMm - originMm_) / voxelSizeMm_ - 0.5);
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
    return traverseFrom(stack, top, budget, reach, [&](const glm::ivec3& v, std::uint32_t node) {
      if (segment.distanceSq(glm::dvec3(v)) <= r2) leaf(v, node);
    });
  };
  if (!cache) {
    walkWhole(scratch, walkFrom, aMm, bMm, radiusMm, [&](const glm::ivec3& v, std::uint32_t) { fn(v); });
    return;
  }
  const dph_detail::Segment segment((aMm - originMm_) / voxelSizeMm_ - 0.5, (bMm - originMm_) / voxelSizeMm_ - 0.5);
  const double r = radiusMm / voxelSizeMm_;
  const double r2 = r * r;
  answerThroughCache(2, aMm, bMm, radiusMm, scratch, *cache, walkFrom,
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
