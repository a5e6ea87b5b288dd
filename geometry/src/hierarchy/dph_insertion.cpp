// The hierarchy's insertion build (seed section 3.3, Fig. 3): each level's nodes join the first
// parent cell that holds them, in a seeded random order, for any input the lattice build
// does not take.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "dph_internal.h"
#include "osteon/core/error.h"
#include "osteon/geometry/hierarchy/dph.h"

namespace osteon::geometry {

using namespace dph_detail;

namespace {

// Each node of `below`, in `order`, joins the first parent (in `above`, by index) whose cell
// (centre within `half`) holds it, or starts a new parent at its centre. Parent centres are
// bucketed on a lattice of the cell edge: the cells that can hold a centre c have their
// centres within `half` of it, so they sit in the (at most 2 x 2 x 2) lattice cells
// overlapping [c - half, c + half]; a lattice cell holds at most 8 parent centres, since
// parent centres are more than `half` apart. Dense heads while the lattice is small against
// the node count, a hash map for sparse inputs.
template <typename LevelT>
void assignParents(LevelT& below, LevelT& above, const std::vector<std::uint32_t>& order,
                   long long cellEdge, long long half) {
  const std::size_t count = below.centre.size();
  glm::ivec3 minCentre(std::numeric_limits<int>::max());
  glm::ivec3 maxCentre(std::numeric_limits<int>::min());
  for (const glm::ivec3& c : below.centre) {
    minCentre = glm::min(minCentre, c);
    maxCentre = glm::max(maxCentre, c);
  }
  long long latticeLo[3], latticeDims[3];
  for (int a = 0; a < 3; ++a) {
    latticeLo[a] = floorDiv(minCentre[a], cellEdge);
    latticeDims[a] = floorDiv(maxCentre[a], cellEdge) - latticeLo[a] + 1;
  }
  const long long latticeCells = latticeDims[0] * latticeDims[1] * latticeDims[2];
  const bool dense = latticeCells <= 4 * (long long)count + (1LL << 20);
  std::vector<std::uint32_t> denseHead(dense ? std::size_t(latticeCells) : 0,
                                       DynamicProximityHierarchy::kNone);
  std::unordered_map<std::uint64_t, std::uint32_t> sparseHead;
  const auto latticeIndex = [&](long long lx, long long ly, long long lz) {
    return std::uint64_t((lx - latticeLo[0]) +
                         latticeDims[0] *
                             ((ly - latticeLo[1]) + latticeDims[1] * (lz - latticeLo[2])));
  };
  const auto headOf = [&](std::uint64_t cell) {
    if (dense) return denseHead[cell];
    const auto it = sparseHead.find(cell);
    return it == sparseHead.end() ? DynamicProximityHierarchy::kNone : it->second;
  };
  const auto setHead = [&](std::uint64_t cell, std::uint32_t parent) {
    if (dense) {
      denseHead[cell] = parent;
    } else {
      sparseHead[cell] = parent;
    }
  };

  std::vector<std::uint32_t> nextInCell;
  for (const std::uint32_t node : order) {
    const glm::ivec3 c = below.centre[node];
    long long from[3], to[3];
    for (int a = 0; a < 3; ++a) {
      from[a] = std::max(floorDiv(c[a] - half, cellEdge), latticeLo[a]);
      to[a] = std::min(floorDiv(c[a] + half, cellEdge), latticeLo[a] + latticeDims[a] - 1);
    }
    std::uint32_t chosen = DynamicProximityHierarchy::kNone;
    for (long long lz = from[2]; lz <= to[2]; ++lz)
      for (long long ly = from[1]; ly <= to[1]; ++ly)
        for (long long lx = from[0]; lx <= to[0]; ++lx) {
          for (std::uint32_t p = headOf(latticeIndex(lx, ly, lz));
               p != DynamicProximityHierarchy::kNone; p = nextInCell[p]) {
            if (p < chosen && chebyshev(above.centre[p], c) <= half) chosen = p;
          }
        }
    if (chosen ==
        DynamicProximityHierarchy::kNone) {  // not covered: a new parent at this node's centre
      chosen = std::uint32_t(above.centre.size());
      above.centre.push_back(c);
      const std::uint64_t cell =
          latticeIndex(floorDiv(c.x, cellEdge), floorDiv(c.y, cellEdge), floorDiv(c.z, cellEdge));
      nextInCell.push_back(headOf(cell));
      setHead(cell, chosen);
    }
    below.parent[node] = chosen;
  }
}

// A new level's nodes from their regrouped children: child ranges, alive counts and boxes.
template <typename LevelT>
void finishLevel(LevelT& above, const LevelT& below, const std::vector<std::uint32_t>& firstSlot,
                 bool leaves, std::size_t& maxChildren) {
  const std::size_t parents = above.centre.size();
  above.parent.assign(parents, DynamicProximityHierarchy::kNone);
  above.alive.assign(parents, 1);
  above.aliveCount = parents;
  above.childBegin.assign(firstSlot.begin(), firstSlot.end() - 1);
  above.childEnd.assign(firstSlot.begin() + 1, firstSlot.end());
  above.aliveChildren.resize(parents);
  above.boxMin.assign(parents, glm::ivec3(std::numeric_limits<int>::max()));
  above.boxMax.assign(parents, glm::ivec3(std::numeric_limits<int>::min()));
  for (std::uint32_t p = 0; p < parents; ++p) {
    above.aliveChildren[p] = above.childEnd[p] - above.childBegin[p];
    maxChildren = std::max<std::size_t>(maxChildren, above.aliveChildren[p]);
    for (std::uint32_t c = above.childBegin[p]; c < above.childEnd[p]; ++c) {
      const glm::ivec3 lo = leaves ? below.centre[c] : below.boxMin[c];
      const glm::ivec3 hi = leaves ? below.centre[c] : below.boxMax[c];
      above.boxMin[p] = glm::min(above.boxMin[p], lo);
      above.boxMax[p] = glm::max(above.boxMax[p], hi);
    }
  }
}

}  // namespace

void DynamicProximityHierarchy::buildInsertion(const std::vector<glm::ivec3>& voxels,
                                               const DphBuildOptions& options) {
  DynamicProximityHierarchy& h = *this;
  const int xi = xi_;
  const std::size_t n = voxels.size();
  // Level 0: one node per voxel, in the given order.
  {
    Level level0;
    level0.centre = voxels;
    level0.parent.assign(n, kNone);
    level0.alive.assign(n, 1);
    level0.aliveCount = n;
    h.levels_.push_back(std::move(level0));
    h.halfWidth_.push_back(0);
  }

  std::mt19937_64 rng(options.seed);
  long long cellEdge = 1;  // xi^L
  for (int L = 0; h.levels_[std::size_t(L)].centre.size() > 1; ++L) {
    cellEdge *= xi;
    const long long half = (cellEdge - 1) / 2;
    Level& below = h.levels_[std::size_t(L)];
    const std::size_t count = below.centre.size();

    // Insertion order: seeded Fisher-Yates (spelled out so every platform agrees).
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    if (options.shuffle) {
      for (std::size_t i = count; i > 1; --i) {
        std::swap(order[i - 1], order[std::size_t(rng() % i)]);
      }
    }

    Level above;
    assignParents(below, above, order, cellEdge, half);

    // Regroup this level so each parent's children are contiguous (stable counting sort).
    const std::size_t parents = above.centre.size();
    std::vector<std::uint32_t> firstSlot(parents + 1, 0);
    for (std::size_t i = 0; i < count; ++i) ++firstSlot[below.parent[i] + 1];
    std::partial_sum(firstSlot.begin(), firstSlot.end(), firstSlot.begin());
    std::vector<std::uint32_t> regroup(count);  // new position -> old index
    std::vector<std::uint32_t> newIndex(count);
    {
      std::vector<std::uint32_t> fillPos(firstSlot.begin(), firstSlot.end() - 1);
      for (std::uint32_t i = 0; i < count; ++i) {
        const std::uint32_t slot = fillPos[below.parent[i]]++;
        regroup[slot] = i;
        newIndex[i] = slot;
      }
    }
    permute(below.centre, regroup);
    permute(below.parent, regroup);
    permute(below.alive, regroup);
    permute(below.childBegin, regroup);
    permute(below.childEnd, regroup);
    permute(below.aliveChildren, regroup);
    permute(below.boxMin, regroup);
    permute(below.boxMax, regroup);
    if (L > 0) {
      for (std::uint32_t& p : h.levels_[std::size_t(L) - 1].parent) p = newIndex[p];
    }

    finishLevel(above, below, firstSlot, L == 0, h.maxChildren_);
    h.levels_.push_back(std::move(above));
    h.halfWidth_.push_back(half);
  }

  // Voxel -> level-0 node, by binary search over packed coordinates.
  const Level& level0 = h.levels_[0];
  std::vector<std::uint32_t> byKey(n);
  std::iota(byKey.begin(), byKey.end(), 0u);
  std::vector<std::uint64_t> keys(n);
  for (std::size_t i = 0; i < n; ++i) keys[i] = packVoxel(level0.centre[i]);
  std::sort(byKey.begin(), byKey.end(),
            [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
  h.voxelKeys_.resize(n);
  h.voxelNodes_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    h.voxelKeys_[i] = keys[byKey[i]];
    h.voxelNodes_[i] = byKey[i];
    if (i > 0 && h.voxelKeys_[i] == h.voxelKeys_[i - 1]) {
      const glm::ivec3 v = level0.centre[byKey[i]];
      throw InputError("hierarchy: voxel (" + std::to_string(v.x) + ", " + std::to_string(v.y) +
                       ", " + std::to_string(v.z) + ") given twice");
    }
  }
}

}  // namespace osteon::geometry
