// Dynamic refinement near the tool (seed section 3.5, sharpened): level-0 voxels within a
// margin of a cutting part's outer sphere, or within reach of another part's shell, split
// into 8 (level -1) or 64 (level -2) sub-voxels, so
// collision, forces and material removal work at half or a quarter of the base voxel size.
//
// Rules (ours, stricter than the seed's):
// - Sub-voxel fill counts volume in the grid's fill units (1/16320 of a level-0 voxel), so a
//   level -2 sub-voxel is full at 255 and a level -1 one at 2040, and the parent's fill in the
//   grid is at every moment exactly the sum of its sub-voxels'. Volume is conserved exactly.
// - Where the source mesh is known (a FineFillSource), sub-voxel fills come from the mesh
//   sampled at the level -2 size, scaled to sum exactly to the parent's fill; otherwise the
//   parent's fill is split evenly. Sub-voxels removed earlier stay removed when a voxel is
//   refined again (a removal mask outlives the cell), so no removed bone reappears.
// - Material removal acts on the finest samples present; a level-0 voxel whose last bone is
//   removed leaves the grid and the hierarchy at once.
// - A refined voxel the tool has not come near for `timeoutS` expires: its cell returns to the
//   pool, its parent keeps the summed fill and the mean density of its remaining sub-voxels.
//   Near means within the refinement margin of a cutting part (refineAround), within reach of
//   another part's shell (refineNearSegment: a drill's shaft refines the bone it touches), or
//   opened by a sample query of any part (a drill's shaft pushing on a tunnel's wall keeps the
//   wall refined where it pushes, so the force there does not drop a level under it).
//
// Everything after construction runs without allocating, locking or throwing: cells come from
// a fixed pool and are found through a fixed open-addressing table. When the pool is full,
// further voxels are left unrefined and counted.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/hierarchy/fine_fill.h"
#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

struct RefinementOptions {
  int depth = 2;                       // 0 (off), 1 (level -1, 8 sub-voxels) or 2 (level -2, 64)
  double marginMm = -1.0;              // beyond the tool's outer sphere; < 0: one finest sample
  double timeoutS = 2.0;               // a refined voxel expires this long after the tool left
  std::size_t capacity = 4096;         // refined voxels at once (the cell pool)
  std::size_t maskCapacity = 1 << 16;  // voxels whose removed sub-voxels are remembered
};

// One collision sample: a level-0 voxel or a refined sub-voxel with bone.
struct VoxelSample {
  glm::dvec3 centreMm;
  double sizeMm;
  int level;  // 0, -1 or -2
  Fill fill;  // in grid fill units (full: kFillFull >> (3 * -level))
  Density density;
};

class RefinedVoxels {
 public:
  // grid and hierarchy must outlive this object and describe the same voxels; source may be
  // null (sub-voxels then inherit their parent's fill). Throws InputError for bad options.
  RefinedVoxels(VoxelGrid& grid, DynamicProximityHierarchy& hierarchy, const FineFillSource* source,
                const RefinementOptions& options);
  // Bytes held: the pool of refined cells (sized up front), its tables and the removal masks.
  std::size_t memoryBytes() const;

  // Refines (or keeps alive) every voxel within the margin of the tool's outer sphere.
  // Returns the number of voxels newly refined.
  // `cache` (may be null): the hierarchy query's cache for this call site (dph.h).
  int refineAround(const glm::dvec3& toolCentreMm, double outerRadiusMm, double nowS,
                   DphNearCache* cache = nullptr);
  // Refines (or keeps alive) the voxels with bone that a part's shell around the segment a-b
  // (a point when a == b) of outer radius outerRadiusMm may reach: those whose centre lies
  // within segmentRefineReachMm(outerRadiusMm) of the segment, so a long shaft refines the
  // bone it touches, not its length. At most `budget` voxels are newly refined;
  // the others are left as they are and counted in `deferred`, for a later call to continue
  // (the query's voxels already refined are only kept alive). Returns the number newly refined.
  int refineNearSegment(const glm::dvec3& aMm, const glm::dvec3& bMm, double outerRadiusMm,
                        double nowS, DphNearCache* cache, std::size_t budget, int& deferred);
  // The radii the hierarchy queries reach: refineAround's for a tool of outerRadiusMm,
  // forEachSampleInShell's for a shell of outerMm (refined voxels hold samples half their
  // samples' diagonal from their centre), a cut's of radiusMm (every voxel that may hold a
  // sample whose centre lies in it).
  double refineReachMm(double outerRadiusMm) const {
    return outerRadiusMm + marginMm_ + 0.5 * std::sqrt(3.0) * grid_->voxelSizeMm();
  }
  // Every cube that comes within outerRadiusMm of a segment has its centre within this.
  double segmentRefineReachMm(double outerRadiusMm) const {
    return outerRadiusMm + 0.5 * std::sqrt(3.0) * grid_->voxelSizeMm();
  }
  double shellReachMm(double outerMm) const {
    return outerMm + (depth_ > 0 ? sampleHalfDiagonalMm() : 0.0);
  }
  double cutReachMm(double radiusMm) const;
  // A cache for one query site whose core is lengthMm long (0: a point) and whose queries
  // reach reachMm: sized so that its answers always fit, ready for this hierarchy. Allocates.
  DphNearCache makeNearCache(double lengthMm, double reachMm, double skinMm,
                             std::size_t sliceNodes) const;
  // Expires refined voxels not touched since nowS - timeoutS; returns how many.
  int expire(double nowS);
  int expireAll();

  // Samples whose centre lies within radiusMm of centreMm, at the finest level present:
  // fn(const VoxelSample&).
  template <typename Fn>
  void forEachSampleInSphere(const glm::dvec3& centreMm, double radiusMm, Fn&& fn) {
    forEachSampleNearSegment(
        centreMm, centreMm, radiusMm, [](const glm::dvec3&, double) { return true; }, fn);
  }
  // Samples whose centre lies within radiusMm of the segment a-b (a capsule; a sphere when
  // a == b), opening a refined voxel only when openVoxel(centreMm, halfDiagonalMm) says its
  // cube may hold samples the caller wants (a contact shell culls the rest: 64 tests each).
  template <typename Open, typename Fn>
  void forEachSampleNearSegment(const glm::dvec3& aMm, const glm::dvec3& bMm, double radiusMm,
                                Open&& openVoxel, Fn&& fn) {
    forEachSampleInShell(aMm, bMm, -1.0, radiusMm, nullptr, openVoxel,
                         [&](const VoxelSample& s, const glm::dvec3&) { fn(s); });
  }
  // Samples whose centre lies farther than innerMm (< 0: any) and not farther than outerMm
  // from the segment a-b: fn(const VoxelSample&, const glm::dvec3& toCoreMm), toCoreMm running
  // from the sample's centre to its nearest point of the segment, a + t (b - a) - centre with
  // t = clamp((centre - a) . (b - a) / |b - a|^2, 0, 1), the distance tested being its length.
  // Visits samples in a fixed order (voxels as the hierarchy gives them, sub-voxels x fastest).
  // `cache` (may be null): the hierarchy query's cache for this call site (dph.h); the same
  // samples in the same order with or without it.
  template <typename Open, typename Fn>
  void forEachSampleInShell(const glm::dvec3& aMm, const glm::dvec3& bMm, double innerMm,
                            double outerMm, DphNearCache* cache, Open&& openVoxel, Fn&& fn);

  // ---- Sample mutation: the interface material removal (osteon::simulation) works through ----
  // A refined voxel's samples, edited in place: perEdge^3 of them, x fastest.
  struct SampleBlock {
    glm::ivec3 voxel{0};
    glm::dvec3 cornerMm{0.0};  // the voxel's lowest corner
    double sampleMm = 0.0;     // a sample's edge
    int perEdge = 0;           // 2^depth
    Fill* fill = nullptr;      // per sample (0: no bone)
    Density* density = nullptr;
    std::uint64_t* occupied = nullptr;  // bit i set while fill[i] > 0
    std::uint32_t cell = 0;
  };
  // Opens a refined voxel's samples; false when the voxel is not refined.
  bool openBlock(const glm::ivec3& voxel, SampleBlock& block);
  // After the samples in `removed` (bit i: sample i) of an open block lost all their fill
  // (removedFill in total, the caller having set their fill to 0 and cleared their occupied
  // bits): the parent's fill in the grid drops by as much; a voxel left empty leaves the grid
  // and the hierarchy and its block closes (returns true); otherwise the removal is
  // remembered, so that a later refinement of the voxel cannot bring the bone back.
  bool settleBlock(const SampleBlock& block, std::uint64_t removed, std::uint64_t removedFill);
  // An unrefined voxel: a new density (> 0), or its removal from the grid and the hierarchy.
  void setDensity(const glm::ivec3& voxel, Density density);
  void removeVoxel(const glm::ivec3& voxel);
  // The level-0 voxels whose centre lies within reachMm of the segment a-b (a point when
  // a == b), appended to `out` up to its capacity; false when some did not fit. Collect before
  // editing: removal changes the hierarchy the query walks. `cache` as for forEachSampleInShell.
  bool collectVoxels(const glm::dvec3& aMm, const glm::dvec3& bMm, double reachMm,
                     DphNearCache* cache, std::vector<glm::ivec3>& out);
  const VoxelGrid& grid() const { return *grid_; }

  bool isRefined(const glm::ivec3& voxel) const { return findCell(voxel) != kNoCell; }
  // The refined level-0 voxels now, in no particular order.
  std::vector<glm::ivec3> refinedVoxels() const;
  // The i-th refined voxel, i < refinedCount(), in the same order (no allocation).
  const glm::ivec3& refinedVoxelAt(std::size_t i) const { return cells_[activeList_[i]].voxel; }
  // A refined voxel's samples (the first 8^depth entries, x fastest); false if not refined.
  bool subFill(const glm::ivec3& voxel, std::array<Fill, kSubVoxels>& fill,
               std::array<Density, kSubVoxels>& density) const;
  int depth() const { return depth_; }
  double sampleSizeMm() const { return grid_->voxelSizeMm() / double(1 << depth_); }
  std::size_t refinedCount() const { return active_; }
  std::uint64_t poolExhausted() const { return poolExhausted_; }
  std::uint64_t maskOverflows() const { return maskOverflows_; }
  // Bytes held by refined voxels and removal masks now (0 when nothing is refined or drilled).
  std::size_t bytesInUse() const;

 private:
  static constexpr std::uint32_t kNoCell = 0xffffffffu;
  struct Cell {
    glm::ivec3 voxel;
    double lastNearS;
    std::array<Fill, kSubVoxels> fill;  // level -depth sub-voxels, x fastest
    std::array<Density, kSubVoxels> density;
    std::uint64_t occupied;  // bit i: fill[i] > 0 (rows of bone at a glance)
    // Around a segment: how far every sample with bone lay from the shell (of radii
    // slackInnerMm..slackOuterMm) of the query site whose cache has id slackSite, when it
    // last tested them all, and the site's odometer then. While the site has travelled less
    // than that since, no sample can have entered that shell (a point's distance to a
    // segment moves no more than the segment's ends do; bone only leaves). 0: no stamp.
    std::uint64_t slackSite;
    std::uint64_t slackNm, slackTravelNm;
    double slackInnerMm, slackOuterMm;
  };
  struct Mask {
    std::uint64_t key;      // grid linear index + 1 (0: empty slot)
    std::uint64_t removed;  // level -2 sub-voxels removed
    Fill firstFill;         // the voxel's fill when it was first refined
  };

  std::uint64_t keyOf(const glm::ivec3& v) const;
  std::uint32_t findCell(const glm::ivec3& v) const;
  void insertCell(std::uint64_t key, std::uint32_t cell);
  void eraseCell(std::uint64_t key);
  Mask* findMask(std::uint64_t key);
  Mask* insertMask(std::uint64_t key, Fill firstFill);
  void createCell(const glm::ivec3& voxel, double nowS);
  // Half the diagonal of the cube a refined voxel's sample centres fill (one sample narrower
  // than the voxel): the farthest a sample lies from its voxel's centre.
  double sampleHalfDiagonalMm() const {
    const double vs = grid_->voxelSizeMm();
    return 0.5 * std::sqrt(3.0) * (vs - vs / double(1 << depth_));
  }
  void releaseCell(std::uint32_t cell);
  // The samples of one refined voxel in a shell around a segment (see forEachSampleInShell),
  // tested two at a time with SSE2 where it is there: their indices and toCore vectors.
  struct ShellTerms {
    glm::dvec3 a, ab;
    double invLen2, inner2, outer2;  // inner2 < 0: no inner bound
    double innerMm, outerMm;         // innerMm < 0: no inner bound
  };
  struct ShellHits {
    int count;
    std::array<std::uint8_t, kSubVoxels> index;
    std::array<glm::dvec3, kSubVoxels> toCore;
  };
  // With wantSlack, returns the least distance from a sample with bone to the shell (0 when
  // one lies in it; ShellTerms innerMm/outerMm); else 0.
  double shellSamplesOf(const Cell& cell, const glm::dvec3& cornerMm, const ShellTerms& terms,
                        ShellHits& hits, bool wantSlack = false) const;
  // Per axis, over the voxels within reach of a point p (one more each side): voxel centres
  // c = origin + (i + 0.5) vs, toCore = p - c and its square, as voxelCentreMm and the shell
  // test compute them.
  struct SphereAxes {
    static constexpr int kMaxSize = 64;
    int lo[3];
    unsigned size[3];
    double centre[3][kMaxSize], toCore[3][kMaxSize], sq[3][kMaxSize];
    // False when the window would not fit (a reach of about 30 voxels or more, or a far point).
    bool build(const VoxelGrid& grid, const glm::dvec3& pointMm, double reachMm);
  };
  // The level -2 fills of a voxel as first refined, summing exactly to firstFill.
  void baseSubFill(const glm::ivec3& voxel, Fill firstFill,
                   std::array<Fill, kSubVoxels>& out) const;

  VoxelGrid* grid_;
  DynamicProximityHierarchy* hierarchy_;
  const FineFillSource* source_;
  int depth_;
  double marginMm_;
  double timeoutS_;
  double lastRefineS_ = 0.0;  // nowS of the latest refineAround: when a query's voxels are near
  std::vector<Cell> cells_;
  std::vector<std::uint32_t> freeCells_;
  std::size_t freeTop_ = 0;
  std::vector<std::uint32_t> activeList_;  // cells in use, unordered
  std::vector<std::uint32_t> activeSlot_;  // cell -> position in activeList_
  std::size_t active_ = 0;
  std::vector<std::uint64_t> tableKeys_;  // open addressing, linear probing; 0 = empty
  std::vector<std::uint32_t> tableCells_;
  std::vector<Mask> masks_;
  std::size_t masksUsed_ = 0;
  std::uint64_t poolExhausted_ = 0;
  std::uint64_t maskOverflows_ = 0;
  DphQueryScratch scratch_;
};

template <typename Open, typename Fn>
void RefinedVoxels::forEachSampleInShell(const glm::dvec3& aMm, const glm::dvec3& bMm,
                                         double innerMm, double outerMm, DphNearCache* cache,
                                         Open&& openVoxel, Fn&& fn) {
  const double vs = grid_->voxelSizeMm();
  // A refined voxel may hold samples in reach although its centre is not.
  // Its samples' centres lie within a cube one sample narrower than the voxel: half that
  // cube's diagonal from the voxel's centre.
  const double halfDiagonal = sampleHalfDiagonalMm();
  const double reach = shellReachMm(outerMm);
  ShellTerms terms;
  terms.a = aMm;
  terms.ab = bMm - aMm;
  const double len2 = glm::dot(terms.ab, terms.ab);
  terms.invLen2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
  terms.inner2 = innerMm < 0.0 ? -1.0 : innerMm * innerMm;
  terms.outer2 = outerMm * outerMm;
  terms.innerMm = innerMm;
  terms.outerMm = outerMm;
  ShellHits hits;
  // Around a point (a sphere, the drill's tip) an unrefined voxel's centre and toCore come from
  // per-axis tables over the query's window, the same values the formulas below give: every
  // voxel of a static run is read this way.
  SphereAxes axes;
  const bool tabled = len2 == 0.0 && axes.build(*grid_, aMm + 0.0 * terms.ab, reach);
  const auto visit = [&](const glm::ivec3& v) {
    const std::uint32_t cell = active_ == 0 ? kNoCell : findCell(v);
    if (tabled && cell == kNoCell) {
      const auto ix = unsigned(v.x - axes.lo[0]), iy = unsigned(v.y - axes.lo[1]),
                 iz = unsigned(v.z - axes.lo[2]);
      if (ix < axes.size[0] && iy < axes.size[1] && iz < axes.size[2]) {
        const double d2 = axes.sq[0][ix] + axes.sq[1][iy] + axes.sq[2][iz];
        if (d2 > terms.inner2 && d2 <= terms.outer2) {
          VoxelSample s{{axes.centre[0][ix], axes.centre[1][iy], axes.centre[2][iz]}, vs, 0, 0, 0};
          grid_->fillAndDensity(v, s.fill, s.density);
          fn(s, glm::dvec3(axes.toCore[0][ix], axes.toCore[1][iy], axes.toCore[2][iz]));
        }
        return;
      }
    }
    const glm::dvec3 c = grid_->voxelCentreMm(v);
    if (cell == kNoCell) {
      double t = glm::dot(c - aMm, terms.ab) * terms.invLen2;
      t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
      const glm::dvec3 toCore = aMm + t * terms.ab - c;
      const double d2 = glm::dot(toCore, toCore);
      if (d2 > terms.inner2 && d2 <= terms.outer2) {
        VoxelSample s{c, vs, 0, 0, 0};
        grid_->fillAndDensity(v, s.fill, s.density);
        fn(s, toCore);
      }
      return;
    }
    if (!openVoxel(c, halfDiagonal)) return;
    Cell& cl = cells_[cell];
    cl.lastNearS = std::max(cl.lastNearS, lastRefineS_);
    // Around a segment through a cache: skip the voxel while the site has not travelled its
    // slack (a margin far above the rounding of distances and travel).
    const bool slackable = cache && len2 > 0.0;
    if (slackable && cl.slackSite == cache->id() && cl.slackInnerMm == innerMm &&
        cl.slackOuterMm == outerMm && cache->travelNm() - cl.slackTravelNm < cl.slackNm) {
      return;
    }
    const glm::dvec3 corner = grid_->worldFromGrid(glm::dvec3(v));
    const double slack = shellSamplesOf(cl, corner, terms, hits, slackable);
    if (slackable) {
      // In whole nanometres, rounded down and one less for the rounding of the distances.
      cl.slackSite = cache->id();
      cl.slackNm = !(slack >= 0.0) ? 0
                   : slack < 1e6   ? std::uint64_t(std::max(std::floor(slack * 1e6) - 1.0, 0.0))
                                   : std::uint64_t(1) << 39;
      cl.slackTravelNm = cache->travelNm();
      cl.slackInnerMm = innerMm;
      cl.slackOuterMm = outerMm;
    }
    const int n = 1 << depth_;
    const double sub = vs / n;
    for (int h = 0; h < hits.count; ++h) {
      const int i = hits.index[std::size_t(h)];
      // Sub-voxel coordinates by shifts (n is a power of two), not integer divisions.
      const glm::ivec3 k(i & (n - 1), (i >> depth_) & (n - 1), i >> (2 * depth_));
      const glm::dvec3 sc = corner + (glm::dvec3(k) + 0.5) * sub;
      fn(VoxelSample{sc, sub, -depth_, cl.fill[std::size_t(i)], cl.density[std::size_t(i)]},
         hits.toCore[std::size_t(h)]);
    }
  };
  if (len2 > 0.0) {
    hierarchy_->forEachVoxelInCapsule(aMm, bMm, reach, scratch_, cache, visit);
  } else {
    hierarchy_->forEachVoxelInSphere(aMm, reach, scratch_, cache, visit);
  }
}

}  // namespace osteon::geometry
