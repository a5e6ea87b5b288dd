// Dynamic Proximity Hierarchy over level-0 voxels (seed section 3.3).
//
// Level 0 holds one node per occupied voxel. A node at level L covers a cube of xi^L voxels
// (xi, the expansion ratio, odd so the cube is centred on a voxel). Two builds give valid
// hierarchies with the same query answers (as sets):
// - lattice (default): the cells of level L tile space from the voxels' lowest corner, so a
//   node's parent is the cell holding it. The voxels are sorted once by a base-xi Morton key
//   (radix sort, O(n)); then every level is already grouped by parent and is one linear pass.
//   From a grid (xi 3) the level-1 cells are read from the bricks' occupancy in one parallel
//   pass and only the cells are sorted. Level 0 keeps no coordinates, only each voxel's
//   place in its level-1 cell (2 bytes): about 5 bytes a voxel in all on a solid bone.
// - insertion (the seed's Fig. 3): the nodes of level L are taken in a seeded random order;
//   a node whose centre lies in the cell of an existing level-(L+1) node becomes that node's
//   child (the earliest created, when several cells hold it); otherwise it creates a new
//   level-(L+1) node at its own centre. O(n) per level with a hash of cells, cache-hostile.
//
// Queries descend from the root and prune any subtree whose box of level-0 descendants is out
// of reach. Removing a voxel removes its node and every ancestor left without children.
// Nothing here allocates after construction except the caller-owned QueryScratch, which grows
// once to its bound; queries and removals are safe in the 1 kHz loop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::geometry {

enum class DphBuildMethod {
  kLattice,    // cells on a fixed lattice, built bottom-up in Morton order: O(n)
  kInsertion,  // the seed's insertion (seed, shuffle): kept for Fig. 3 and as a reference
};

struct DphBuildOptions {
  int expansionRatio = 3;  // xi: odd, 3..15
  DphBuildMethod method = DphBuildMethod::kLattice;
  std::uint64_t seed = 1;  // kInsertion: insertion order at every level
  bool shuffle =
      true;  // kInsertion; false: level 0 in the given order, higher levels in creation order
};

// Caller-owned traversal memory, so queries never allocate once it has grown.
struct DphQueryScratch {
  std::vector<std::uint64_t> stack;  // (level << 32) | node
};

class DynamicProximityHierarchy;

// A query's answer kept for the queries that follow it nearby: the voxels within the query's
// radius plus a skin, in the order the hierarchy gave them (a neighbour list with a skin, as
// molecular dynamics keeps them). A later query whose sphere or capsule lies inside the kept,
// inflated one (each end moved less than the skin) is answered by testing the kept voxels
// that are still in the hierarchy. The answer is the walk's, voxel for voxel and in the same
// order: pruning keeps the depth-first order of the voxels it visits, and voxels are only
// ever removed. A tool in contact moves micrometres per millisecond, so one walk serves many
// steps.
//
// A walk meets hierarchy nodes the kept answers never touch, so it runs from cold memory
// (several times a warm walk's time). With slices on, once the tool has used a third of the
// skin the next answer is gathered around where it is then, `sliceNodes` nodes per query,
// and takes over when complete; a query walks at once only when no kept answer covers it (the
// first, a jump, a tool faster than the slices).
//
// One cache per query site (a tool part's shell, its cut); caller-owned, sized up front
// (capacity, and reserveFor the hierarchy's traversal), never allocating in a query. A walk
// whose answer would not fit is answered directly and counted.
class DphNearCache {
 public:
  DphNearCache();
  // skinMm >= 0; capacity: voxels kept at most; sliceNodes: nodes per query for the next
  // answer (0: no slices, walk when the kept answer no longer covers).
  DphNearCache(double skinMm, std::size_t capacity, std::size_t sliceNodes = 0);
  // Move-only: a cache's id stands for its odometer (see travelNm), which a copy would fork.
  // The moved-from cache gets a new id and a zero odometer.
  DphNearCache(const DphNearCache&) = delete;
  DphNearCache& operator=(const DphNearCache&) = delete;
  DphNearCache(DphNearCache&& other) noexcept;
  DphNearCache& operator=(DphNearCache&& other) noexcept;
  ~DphNearCache() = default;
  // Room for every voxel of a capsule (a sphere at lengthMm 0) of radiusMm, skin included,
  // in a grid of voxelMm: the capacity a query site needs so that its answers always fit.
  static std::size_t capacityFor(double lengthMm, double radiusMm, double voxelMm);
  // Sizes the slices' traversal stack for h (slices wait until it is sized).
  void reserveFor(const DynamicProximityHierarchy& h);
  double skinMm() const { return skinMm_; }
  std::size_t capacity() const { return kept_.nodes.capacity(); }
  std::uint64_t walks() const { return walks_; }    // queries that had to walk at once
  std::uint64_t reuses() const { return reuses_; }  // queries answered from a kept answer
  std::uint64_t sliced() const { return sliced_; }  // answers gathered in slices
  std::uint64_t overflows() const { return overflows_; }
  // How far the query's ends have moved in all, in whole nanometres: per query max(|da|,
  // |db|) rounded up (and a non-finite move as a jump beyond any slack), summed exactly in
  // integers. Between two queries of this cache no point's distance to the query's segment
  // has changed by more than the difference of their readings.
  std::uint64_t travelNm() const { return travelNm_; }
  // Unique to this cache (never reused, also not by a moved-into cache at the same address).
  std::uint64_t id() const { return id_; }
  void clear() {
    kept_.reachMm = -1.0;
    next_.reachMm = -1.0;
    slicing_ = false;
  }

 private:
  friend class DynamicProximityHierarchy;
  struct Answer {
    std::vector<std::uint32_t> nodes;  // level-0 nodes, walk order
    std::vector<glm::ivec3> centres;
    glm::dvec3 aMm{0.0}, bMm{0.0};
    double reachMm = -1.0;  // < 0: nothing kept
    void reserve(std::size_t capacity);
    bool add(const glm::ivec3& v, std::uint32_t node) {
      if (nodes.size() == nodes.capacity()) return false;
      nodes.push_back(node);
      centres.push_back(v);
      return true;
    }
  };
  // How far the query's ends lie from the answer's: max(|a - a0|, |b - b0|).
  static double moved(const Answer& answer, const glm::dvec3& a, const glm::dvec3& b);
  bool covers(const DynamicProximityHierarchy& h, const Answer& answer, const glm::dvec3& a,
              const glm::dvec3& b, double radiusMm) const;

  const DynamicProximityHierarchy* owner_ = nullptr;
  std::uint64_t generation_ = 0;
  double skinMm_ = 0.0;
  std::size_t sliceNodes_ = 0;
  Answer kept_, next_;
  bool slicing_ = false;  // next_ is being gathered
  bool nextFits_ = true;
  std::vector<std::uint64_t> stack_;  // the slices' traversal
  std::size_t top_ = 0;
  std::uint64_t walks_ = 0, reuses_ = 0, sliced_ = 0, overflows_ = 0;
  std::uint64_t id_ = 0;
  std::uint64_t travelNm_ = 0;
  glm::dvec3 lastAMm_{0.0}, lastBMm_{0.0};
  bool travelled_ = false;
  int nextKind_ = 0;  // the query kind gathering next_ (slices continue only for the same kind)
  void recordTravel(const glm::dvec3& a, const glm::dvec3& b);
};

class DynamicProximityHierarchy {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  DynamicProximityHierarchy() = default;

  // From voxel coordinates (grid indices; any z, so a z = 0 slice gives the seed's 2-D case).
  // worldFromGrid: voxel v has its centre at originMm + (v + 0.5) * voxelSizeMm.
  // Throws InputError for an even or out-of-range xi, or duplicate voxels. The lattice build
  // falls back to insertion (in the given order) for extents whose Morton key needs > 64 bits
  // (beyond 1.5 M voxels along an axis at xi 3).
  static DynamicProximityHierarchy build(const std::vector<glm::ivec3>& voxels,
                                         const DphBuildOptions& options,
                                         glm::dvec3 originMm = glm::dvec3(0.0),
                                         double voxelSizeMm = 1.0);
  // Over the grid's occupied voxels (fill > 0).
  static DynamicProximityHierarchy build(const VoxelGrid& grid, const DphBuildOptions& options);

  int expansionRatio() const { return xi_; }
  int levelCount() const { return int(levels_.size()); }
  std::size_t nodeCount(int level) const { return levels_[std::size_t(level)].aliveCount; }
  // Node slots at a level, removed ones included (iterate 0..nodeSlots-1 with alive()).
  std::size_t nodeSlots(int level) const { return levels_[std::size_t(level)].alive.size(); }
  std::size_t voxelCount() const { return levels_.empty() ? 0 : levels_[0].aliveCount; }
  // Half the cell edge at a level, in voxels: (xi^L - 1) / 2.
  long long halfWidth(int level) const { return halfWidth_[std::size_t(level)]; }
  // Index of the root at the top level, or kNone once every voxel is removed.
  std::uint32_t root() const;
  glm::ivec3 centre(int level, std::uint32_t node) const {
    return level == 0 && compactVoxels() ? voxelInCell(parent(0, node), node)
                                         : levels_[std::size_t(level)].centre[node];
  }
  // O(log n) for a voxel of the lattice build, which keeps no parent per voxel.
  std::uint32_t parent(int level, std::uint32_t node) const;
  bool alive(int level, std::uint32_t node) const {
    return levels_[std::size_t(level)].alive[node] != 0;
  }
  // Children of a node at level >= 1: indices [childBegin, childEnd) at level - 1 (dead
  // ones included; check alive()).
  std::uint32_t childBegin(int level, std::uint32_t node) const {
    return levels_[std::size_t(level)].childBegin[node];
  }
  std::uint32_t childEnd(int level, std::uint32_t node) const {
    return levels_[std::size_t(level)].childEnd[node];
  }

  bool contains(const glm::ivec3& voxel) const { return findVoxel(voxel) != kNone; }
  // Removes the voxel's node and prunes ancestors left without children. O(levels + log n).
  // Returns false when the voxel is not in the hierarchy.
  bool removeVoxel(const glm::ivec3& voxel);

  glm::dvec3 voxelCentreMm(const glm::ivec3& v) const {
    return originMm_ + (glm::dvec3(v) + 0.5) * voxelSizeMm_;
  }
  double voxelSizeMm() const { return voxelSizeMm_; }

  // Every voxel whose centre lies within radiusMm of centreMm: fn(const glm::ivec3&).
  // With a cache, the same voxels in the same order, from the cache when it covers the query.
  template <typename Fn>
  void forEachVoxelInSphere(const glm::dvec3& centreMm, double radiusMm, DphQueryScratch& scratch,
                            Fn&& fn) const {
    forEachVoxelInSphere(centreMm, radiusMm, scratch, nullptr, fn);
  }
  template <typename Fn>
  void forEachVoxelInSphere(const glm::dvec3& centreMm, double radiusMm, DphQueryScratch& scratch,
                            DphNearCache* cache, Fn&& fn) const;
  // Every voxel whose centre lies within radiusMm of the segment aMm-bMm.
  template <typename Fn>
  void forEachVoxelInCapsule(const glm::dvec3& aMm, const glm::dvec3& bMm, double radiusMm,
                             DphQueryScratch& scratch, Fn&& fn) const {
    forEachVoxelInCapsule(aMm, bMm, radiusMm, scratch, nullptr, fn);
  }
  template <typename Fn>
  void forEachVoxelInCapsule(const glm::dvec3& aMm, const glm::dvec3& bMm, double radiusMm,
                             DphQueryScratch& scratch, DphNearCache* cache, Fn&& fn) const;
  // The voxel whose centre is nearest to pointMm (ties: any); false when empty.
  bool nearestVoxel(const glm::dvec3& pointMm, DphQueryScratch& scratch, glm::ivec3& voxel,
                    double& distanceMm) const;

  // Checks every invariant; returns "" or a description of the first violation:
  // each alive child's centre inside its parent's cell; child ranges and alive-child counts
  // consistent; boxes enclosing their descendants; exactly one alive node at the top level
  // while any voxel is left; every alive node below the top has an alive parent.
  std::string validate() const;
  // Also checks that the level-0 nodes are exactly the grid's occupied voxels.
  std::string validateAgainst(const VoxelGrid& grid) const;

  std::size_t memoryBytes() const;
  // True when built on the lattice (see the top of this file).
  bool latticeBuilt() const { return lattice_; }
  // Distinct for every build (copies share it): a cache kept from one never answers another.
  std::uint64_t generation() const { return generation_; }
  // Entries a depth-first traversal's stack needs at most.
  std::size_t traversalStackSize() const;

 private:
  struct Level {
    std::vector<glm::ivec3> centre;     // level 0 of the lattice build: empty (see digit)
    std::vector<std::uint16_t> digit;   // lattice level 0: the voxel's place in its level-1 cell
    std::vector<std::uint32_t> parent;  // lattice level 0: empty
    std::vector<std::uint32_t> childBegin;     // level >= 1
    std::vector<std::uint32_t> childEnd;       // level >= 1
    std::vector<std::uint32_t> aliveChildren;  // level >= 1
    std::vector<glm::ivec3> boxMin;            // level >= 1: bounds of level-0 descendants
    std::vector<glm::ivec3> boxMax;
    std::vector<std::uint8_t> alive;
    std::size_t aliveCount = 0;
  };

  // The voxel's level-0 node, and its level-1 cell when cell is given.
  std::uint32_t findVoxel(const glm::ivec3& voxel, std::uint32_t* cell = nullptr) const;
  // Level 0 kept as digits (the lattice build over more than one voxel).
  bool compactVoxels() const { return !levels_.empty() && !levels_[0].digit.empty(); }
  glm::ivec3 voxelInCell(std::uint32_t cell, std::uint32_t node) const {
    return levels_[1].centre[cell] - int(halfWidth_[1]) + digitOffset_[levels_[0].digit[node]];
  }
  // The lattice build (dph_build.cpp); false when the Morton key would not fit in 64 bits.
  bool buildLattice(const std::vector<glm::ivec3>& voxels);
  // The same hierarchy straight from the grid's bricks (xi 3): no voxel list, no voxel sort.
  // False, leaving the grid to the voxel-list build, for fewer than 2 voxels or too wide a key.
  bool buildLatticeFromGrid(const VoxelGrid& grid);
  // Lattice origin, key spread and digit offsets for the occupied bounds lo..hi.
  bool prepareLattice(const glm::ivec3& lo, const glm::ivec3& hi, int& keyBits);
  // Levels 2 and up from level 1 and its sorted cell keys.
  void buildUpperLevels(std::vector<std::uint64_t> keys);
  void buildInsertion(const std::vector<glm::ivec3>& voxels, const DphBuildOptions& options);
  // Squared distance (voxel units) from a point in grid space to the box of voxel centres.
  double boxDistanceSq(int level, std::uint32_t node, const glm::dvec3& g) const;
  void reserveScratch(DphQueryScratch& scratch) const;
  // leaf(centre, node) for the level-0 nodes of subtrees in reach, depth first.
  template <typename Reach, typename Leaf>
  void traverse(DphQueryScratch& scratch, Reach&& reach, Leaf&& leaf) const;
  // The same walk from a saved stack (top items), for at most `budget` nodes; true when done.
  void startTraversal(std::uint64_t* stack, std::size_t& top) const;
  template <typename Reach, typename Leaf>
  bool traverseFrom(std::uint64_t* stack, std::size_t& top, std::size_t budget, Reach&& reach,
                    Leaf&& leaf) const;
  // A query through a cache. walkFrom(a, b, radiusMm, stack, top, budget, leaf) walks for the
  // query of those ends and radius (see traverseFrom); test(centre) is the walk's own leaf
  // test for this query.
  // A whole walk from the root through walkFrom (see answerThroughCache), in scratch.
  template <typename WalkFrom, typename Leaf>
  void walkWhole(DphQueryScratch& scratch, WalkFrom&& walkFrom, const glm::dvec3& a,
                 const glm::dvec3& b, double radiusMm, Leaf&& leaf) const;
  // kind: 1 sphere, 2 capsule (a slice started by one is not continued by the other).
  template <typename WalkFrom, typename Test, typename Fn>
  void answerThroughCache(int kind, const glm::dvec3& a, const glm::dvec3& b, double radiusMm,
                          DphQueryScratch& scratch, DphNearCache& cache, WalkFrom&& walkFrom,
                          Test&& test, Fn&& fn) const;

  int xi_ = 3;
  glm::dvec3 originMm_{0.0};
  double voxelSizeMm_ = 1.0;
  std::vector<long long> halfWidth_;
  std::vector<Level> levels_;
  // Voxel lookup of the insertion build: sorted packed coordinates and their level-0 nodes.
  std::vector<std::uint64_t> voxelKeys_;
  std::vector<std::uint32_t> voxelNodes_;
  // Voxel lookup of the lattice build (about 1 byte a voxel instead of 12): a voxel's Morton
  // key is keySpread_[0][x - o.x] + keySpread_[1][y - o.y] + keySpread_[2][z - o.z]; its
  // level-1 cell, key / xi^3, is found among the sorted cell keys of the level-1 nodes.
  bool lattice_ = false;
  glm::ivec3 latticeOriginVoxel_{0};
  std::vector<std::uint64_t> keySpread_[3];
  std::vector<std::uint64_t> cellKeys_;  // level-1 node i's cell key (ascending)
  std::vector<glm::ivec3> digitOffset_;  // a digit's voxel, from its cell's lowest corner
  std::size_t maxChildren_ = 0;
  std::uint64_t generation_ = 0;
};

}  // namespace osteon::geometry

#include "osteon/geometry/hierarchy/dph_queries.inl"
