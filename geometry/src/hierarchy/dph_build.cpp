// The lattice build of the Dynamic Proximity Hierarchy (see dph.h): the cells of level L tile
// space from the voxels' lowest corner in cubes of xi^L voxels, so a node's parent is simply
// the cell that holds it. Voxels sorted by a base-xi Morton key (the digits of x, y and z
// interleaved, most significant level first) are grouped by their level-1 cell, those cells
// by their level-2 cell, and so on: every level is one linear pass over the one below, with
// no hash, no search and no permutation. The structure depends on the voxel set only, not on
// the input order or the thread count.
#include "osteon/geometry/hierarchy/dph.h"

#include "osteon/core/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>

namespace osteon::geometry {

namespace {

// Bits needed to write values below `count` (at least 1).
int bitsFor(std::uint64_t count) {
  int bits = 1;
  while (bits < 64 && (std::uint64_t(1) << bits) < count) ++bits;
  return bits;
}

// Stable LSD radix sort of `values` on bits [lowBit, lowBit + bits), 11 bits a pass; a pass
// whose digit is the same for every value is skipped (the high digits of small grids).
void radixSort(std::vector<std::uint64_t>& values, int lowBit, int bits) {
  std::vector<std::uint64_t> out(values.size());
  const int passes = (bits + 10) / 11;
  const int digitBits = passes > 0 ? (bits + passes - 1) / passes : 0;
  std::vector<std::size_t> start(std::size_t(1) << digitBits);
  for (int p = 0; p < passes; ++p) {
    const int shift = lowBit + p * digitBits;
    const int width = std::min(digitBits, bits - p * digitBits);
    const std::uint64_t mask = (std::uint64_t(1) << width) - 1;
    std::fill(start.begin(), start.end(), 0);
    for (const std::uint64_t v : values) ++start[std::size_t((v >> shift) & mask)];
    if (*std::max_element(start.begin(), start.end()) == values.size()) continue;
    std::size_t sum = 0;
    for (std::size_t& s : start) {
      const std::size_t c = s;
      s = sum;
      sum += c;
    }
    for (const std::uint64_t v : values) out[start[std::size_t((v >> shift) & mask)]++] = v;
    values.swap(out);
  }
}

}  // namespace

bool DynamicProximityHierarchy::buildLattice(const std::vector<glm::ivec3>& voxels) {
  const std::size_t n = voxels.size();
  const std::uint64_t xi = std::uint64_t(xi_);
  const std::uint64_t cellsPerParent = xi * xi * xi;
  glm::ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
  for (const glm::ivec3& v : voxels) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  // Digit levels: xi^digits must span the widest axis; the key ranges over xi^(3 digits).
  const long long extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) + 1LL;
  int digits = 1;
  for (long long span = xi_; span < extent; span *= xi_) ++digits;
  std::uint64_t keyCount = 1;
  for (int d = 0; d < digits; ++d) {
    if (keyCount > std::numeric_limits<std::uint64_t>::max() / cellsPerParent) return false;
    keyCount *= cellsPerParent;
  }
  const int keyBits = bitsFor(keyCount);
  const int indexBits = bitsFor(n);

  // An axis's share of the key: its base-xi digits, each at its place in a digit triple.
  for (int a = 0; a < 3; ++a) {
    std::vector<std::uint64_t>& spread = keySpread_[a];
    spread.assign(std::size_t(hi[a] - lo[a] + 1), 0);
    const std::uint64_t axisPlace = a == 0 ? 1 : (a == 1 ? xi : xi * xi);
    for (std::size_t c = 0; c < spread.size(); ++c) {
      std::uint64_t rest = c, place = axisPlace, key = 0;
      for (int d = 0; d < digits; ++d, rest /= xi, place *= cellsPerParent) key += (rest % xi) * place;
      spread[c] = key;
    }
  }
  latticeOriginVoxel_ = lo;
  const auto keyOf = [&](const glm::ivec3& v) {
    return keySpread_[0][std::size_t(v.x - lo.x)] + keySpread_[1][std::size_t(v.y - lo.y)] +
           keySpread_[2][std::size_t(v.z - lo.z)];
  };

  // Sort (key, input index) pairs: packed into one word when they fit, the usual case.
  std::vector<std::uint64_t> keys(n);
  std::vector<std::uint32_t> order(n);  // sorted position -> input index
  if (keyBits + indexBits <= 64) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) keys[i] = (keyOf(voxels[i]) << indexBits) | i;
    });
    radixSort(keys, indexBits, keyBits);
    const std::uint64_t indexMask = (std::uint64_t(1) << indexBits) - 1;
    for (std::size_t i = 0; i < n; ++i) {
      order[i] = std::uint32_t(keys[i] & indexMask);
      keys[i] >>= indexBits;
    }
  } else {
    std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs(n);
    for (std::size_t i = 0; i < n; ++i) pairs[i] = {keyOf(voxels[i]), std::uint32_t(i)};
    std::sort(pairs.begin(), pairs.end());
    for (std::size_t i = 0; i < n; ++i) {
      keys[i] = pairs[i].first;
      order[i] = pairs[i].second;
    }
  }
  for (std::size_t i = 1; i < n; ++i) {
    if (keys[i] == keys[i - 1]) {
      const glm::ivec3 v = voxels[order[i]];
      throw InputError("hierarchy: voxel (" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
                       std::to_string(v.z) + ") given twice");
    }
  }

  // Level 0 in key order.
  levels_.clear();
  halfWidth_.clear();
  {
    Level level0;
    level0.centre.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) level0.centre[i] = voxels[order[i]];
    });
    level0.parent.assign(n, kNone);
    level0.alive.assign(n, 1);
    level0.aliveCount = n;
    levels_.push_back(std::move(level0));
    halfWidth_.push_back(0);
  }
  std::vector<std::uint32_t>().swap(order);

  // Each level from the one below: a run of equal key / xi^3 is one parent cell.
  long long cellEdge = 1;
  while (levels_.back().centre.size() > 1) {
    cellEdge *= xi_;
    const std::size_t L = levels_.size() - 1;
    const std::size_t count = levels_[L].centre.size();
    // A first pass counts the parents, so each array is allocated once at its size.
    std::size_t parents = 0;
    for (std::size_t i = 0; i < count; ++parents) {  // a division per parent, not per node
      const std::uint64_t cellEnd = (keys[i] / cellsPerParent + 1) * cellsPerParent;
      while (i < count && keys[i] < cellEnd) ++i;
    }
    Level above;
    above.centre.resize(parents);
    above.parent.assign(parents, kNone);
    above.childBegin.resize(parents);
    above.childEnd.resize(parents);
    above.aliveChildren.resize(parents);
    above.boxMin.resize(parents);
    above.boxMax.resize(parents);
    above.alive.assign(parents, 1);
    above.aliveCount = parents;
    Level& below = levels_[L];
    const bool fromVoxels = L == 0;
    std::size_t p = 0;
    for (std::size_t i = 0; i < count;) {
      const std::uint64_t cell = keys[i] / cellsPerParent;
      const std::uint64_t cellEnd = (cell + 1) * cellsPerParent;  // keys of this cell lie below
      glm::ivec3 bMin = fromVoxels ? below.centre[i] : below.boxMin[i];
      glm::ivec3 bMax = fromVoxels ? below.centre[i] : below.boxMax[i];
      std::size_t j = i;
      for (; j < count && keys[j] < cellEnd; ++j) {
        below.parent[j] = std::uint32_t(p);
        bMin = glm::min(bMin, fromVoxels ? below.centre[j] : below.boxMin[j]);
        bMax = glm::max(bMax, fromVoxels ? below.centre[j] : below.boxMax[j]);
      }
      glm::ivec3 centre;
      for (int a = 0; a < 3; ++a) {
        const long long offset = (long long)below.centre[i][a] - lo[a];
        centre[a] = int(lo[a] + offset / cellEdge * cellEdge + (cellEdge - 1) / 2);
      }
      above.centre[p] = centre;
      above.childBegin[p] = std::uint32_t(i);
      above.childEnd[p] = std::uint32_t(j);
      above.aliveChildren[p] = std::uint32_t(j - i);
      maxChildren_ = std::max<std::size_t>(maxChildren_, j - i);
      above.boxMin[p] = bMin;
      above.boxMax[p] = bMax;
      keys[p] = cell;  // in place: p <= i, and the parents' keys are what the next level sorts by
      ++p;
      i = j;
    }
    keys.resize(parents);
    if (L == 0) cellKeys_ = keys;
    levels_.push_back(std::move(above));
    halfWidth_.push_back((cellEdge - 1) / 2);
  }
  cellKeys_.shrink_to_fit();
  lattice_ = true;
  return true;
}

}  // namespace osteon::geometry
