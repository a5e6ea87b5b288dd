// The lattice build of the Dynamic Proximity Hierarchy (see dph.h): the cells of level L tile
// space from the voxels' lowest corner in cubes of xi^L voxels, so a node's parent is simply
// the cell that holds it. Level-1 cells sorted by a base-xi Morton key (the digits of x, y and
// z interleaved, most significant level first) are grouped by their level-2 cell, those by
// their level-3 cell, and so on: every level is one linear pass over the one below, with no
// hash, no search and no permutation. The structure depends on the voxel set only, not on the
// input order or the thread count.
//
// Level 0 keeps no coordinates: a voxel is its level-1 cell's corner plus its digit, its place
// in the cell (x + xi y + xi^2 z), so the hierarchy costs about 3 bytes a voxel plus its cells.
#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "osteon/core/error.h"
#include "osteon/geometry/hierarchy/dph.h"

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

// Sorts keys (all distinct or not) and returns the permutation: order[i] = the input index of
// the i-th smallest. Ties keep input order.
std::vector<std::uint32_t> sortKeys(std::vector<std::uint64_t>& keys, int keyBits) {
  const std::size_t n = keys.size();
  const int indexBits = bitsFor(n);
  std::vector<std::uint32_t> order(n);
  if (keyBits + indexBits <= 64) {  // (key, index) packed into one word: the usual case
    for (std::size_t i = 0; i < n; ++i) keys[i] = (keys[i] << indexBits) | i;
    radixSort(keys, indexBits, keyBits);
    const std::uint64_t indexMask = (std::uint64_t(1) << indexBits) - 1;
    for (std::size_t i = 0; i < n; ++i) {
      order[i] = std::uint32_t(keys[i] & indexMask);
      keys[i] >>= indexBits;
    }
    return order;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> pairs(n);
  for (std::size_t i = 0; i < n; ++i) pairs[i] = {keys[i], std::uint32_t(i)};
  std::sort(pairs.begin(), pairs.end());
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = pairs[i].first;
    order[i] = pairs[i].second;
  }
  return order;
}

// Masks of a 3x3x3 cell's bits (bit x + 3y + 9z) that have x, y or z equal to 0.
constexpr std::uint32_t kCellX0 = 0x1249249u;  // x = 0: bits 0, 3, 6, ..., 24
constexpr std::uint32_t kCellY0 = 0x01C0E07u;  // y = 0: bits 0-2, 9-11, 18-20
constexpr std::uint32_t kCellZ0 = 0x00001FFu;  // z = 0: bits 0-8

// Lowest and highest coordinate (0..2) present along one axis of a non-empty cell mask.
void axisRange(std::uint32_t mask, std::uint32_t axis0, int step, int& lo, int& hi) {
  lo = 3;
  hi = -1;
  for (int d = 0; d < 3; ++d) {
    if (mask & (axis0 << (d * step))) {
      lo = std::min(lo, d);
      hi = d;
    }
  }
}

}  // namespace

bool DynamicProximityHierarchy::prepareLattice(const glm::ivec3& lo, const glm::ivec3& hi,
                                               int& keyBits) {
  const std::uint64_t xi = std::uint64_t(xi_);
  const std::uint64_t cellsPerParent = xi * xi * xi;
  // Digit levels: xi^digits must span the widest axis; the key ranges over xi^(3 digits).
  const long long extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) + 1LL;
  int digits = 1;
  for (long long span = xi_; span < extent; span *= xi_) ++digits;
  std::uint64_t keyCount = 1;
  for (int d = 0; d < digits; ++d) {
    if (keyCount > std::numeric_limits<std::uint64_t>::max() / cellsPerParent) return false;
    keyCount *= cellsPerParent;
  }
  keyBits = bitsFor(keyCount);
  // An axis's share of the key: its base-xi digits, each at its place in a digit triple.
  for (int a = 0; a < 3; ++a) {
    std::vector<std::uint64_t>& spread = keySpread_[a];
    spread.assign(std::size_t(hi[a] - lo[a] + 1), 0);
    const std::uint64_t axisPlace = a == 0 ? 1 : (a == 1 ? xi : xi * xi);
    for (std::size_t c = 0; c < spread.size(); ++c) {
      std::uint64_t rest = c, place = axisPlace, key = 0;
      for (int d = 0; d < digits; ++d, rest /= xi, place *= cellsPerParent)
        key += (rest % xi) * place;
      spread[c] = key;
    }
  }
  latticeOriginVoxel_ = lo;
  digitOffset_.resize(std::size_t(cellsPerParent));
  for (int d = 0; d < int(cellsPerParent); ++d)
    digitOffset_[std::size_t(d)] = {d % xi_, d / xi_ % xi_, d / (xi_ * xi_)};
  levels_.clear();
  halfWidth_.assign(1, 0);
  maxChildren_ = 0;
  return true;
}

bool DynamicProximityHierarchy::buildLattice(const std::vector<glm::ivec3>& voxels) {
  const std::size_t n = voxels.size();
  const std::uint64_t cellsPerParent = std::uint64_t(xi_) * std::uint64_t(xi_) * std::uint64_t(xi_);
  glm::ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
  for (const glm::ivec3& v : voxels) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  int keyBits = 0;
  if (!prepareLattice(lo, hi, keyBits)) return false;
  const auto keyOf = [&](const glm::ivec3& v) {
    return keySpread_[0][std::size_t(v.x - lo.x)] + keySpread_[1][std::size_t(v.y - lo.y)] +
           keySpread_[2][std::size_t(v.z - lo.z)];
  };
  std::vector<std::uint64_t> keys(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) keys[i] = keyOf(voxels[i]);
                    });
  const std::vector<std::uint32_t> order = sortKeys(keys, keyBits);
  for (std::size_t i = 1; i < n; ++i) {
    if (keys[i] == keys[i - 1]) {
      const glm::ivec3 v = voxels[order[i]];
      throw InputError("hierarchy: voxel (" + std::to_string(v.x) + ", " + std::to_string(v.y) +
                       ", " + std::to_string(v.z) + ") given twice");
    }
  }
  if (n == 1) {  // no level 1 to hold its cell: the root is the voxel
    Level level0;
    level0.centre = voxels;
    level0.parent.assign(1, kNone);
    level0.alive.assign(1, 1);
    level0.aliveCount = 1;
    levels_.push_back(std::move(level0));
    lattice_ = true;
    return true;
  }

  // Level 0 as digits and level 1 from it: a run of equal key / xi^3 is one cell.
  Level level0, level1;
  level0.digit.resize(n);
  level0.alive.assign(n, 1);
  level0.aliveCount = n;
  std::vector<std::uint64_t> cells;
  for (std::size_t i = 0; i < n;) {
    const std::uint64_t cell = keys[i] / cellsPerParent;
    const glm::ivec3 first = voxels[order[i]];
    glm::ivec3 bMin = first, bMax = first;
    std::size_t j = i;
    for (; j < n && keys[j] / cellsPerParent == cell; ++j) {
      const glm::ivec3 v = voxels[order[j]];
      level0.digit[j] = std::uint16_t(keys[j] % cellsPerParent);
      bMin = glm::min(bMin, v);
      bMax = glm::max(bMax, v);
    }
    glm::ivec3 corner;
    for (int a = 0; a < 3; ++a) corner[a] = lo[a] + (first[a] - lo[a]) / xi_ * xi_;
    level1.centre.push_back(corner + (xi_ - 1) / 2);
    level1.childBegin.push_back(std::uint32_t(i));
    level1.childEnd.push_back(std::uint32_t(j));
    level1.aliveChildren.push_back(std::uint32_t(j - i));
    level1.boxMin.push_back(bMin);
    level1.boxMax.push_back(bMax);
    maxChildren_ = std::max<std::size_t>(maxChildren_, j - i);
    cells.push_back(cell);
    i = j;
  }
  level1.parent.assign(cells.size(), kNone);
  level1.alive.assign(cells.size(), 1);
  level1.aliveCount = cells.size();
  levels_.push_back(std::move(level0));
  levels_.push_back(std::move(level1));
  halfWidth_.push_back((xi_ - 1) / 2);
  buildUpperLevels(std::move(cells));
  return true;
}

namespace {

// A non-empty cell of the lattice found by the grid's scan.
struct LatticeCell {
  glm::ivec3 corner;
  std::uint32_t mask;  // bit x + 3y + 9z: that voxel of the cell is occupied
};

// Bounds of the occupied voxels (uniform bricks whole, the others voxel by voxel), and their
// count.
std::uint64_t occupiedBounds(const VoxelGrid& grid, glm::ivec3& lo, glm::ivec3& hi) {
  constexpr int B = VoxelGrid::kBrickSize;
  const glm::ivec3 dims = grid.dims();
  lo = glm::ivec3(std::numeric_limits<int>::max());
  hi = glm::ivec3(std::numeric_limits<int>::min());
  std::uint64_t occupied = 0;
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    const VoxelGrid::Brick* b = grid.brickData(brick);
    if (!b && grid.brickUniformFill(brick) == 0) continue;
    const glm::ivec3 bLo = grid.brickCoord(brick) * B;
    const glm::ivec3 bHi = glm::min(bLo + B, dims) - 1;
    if (!b) {
      lo = glm::min(lo, bLo);
      hi = glm::max(hi, bHi);
      occupied += std::uint64_t(bHi.x - bLo.x + 1) * std::uint64_t(bHi.y - bLo.y + 1) *
                  std::uint64_t(bHi.z - bLo.z + 1);
      continue;
    }
    for (int z = bLo.z; z <= bHi.z; ++z)
      for (int y = bLo.y; y <= bHi.y; ++y)
        for (int x = bLo.x; x <= bHi.x; ++x) {
          if (b->fill[std::size_t(VoxelGrid::voxelInBrick(glm::ivec3(x, y, z) - bLo))] == 0)
            continue;
          lo = glm::min(lo, glm::ivec3(x, y, z));
          hi = glm::max(hi, glm::ivec3(x, y, z));
          ++occupied;
        }
  }
  return occupied;
}

// One layer of cells (xi voxels in z): its rows of occupancy bits (bit x of row (y, z)) in
// `rows`, and the non-empty cells it holds appended to `cells`, in scan order. A layer has
// 3 cellDims.y rows per z, so a cell's last row never runs past them.
void scanLayer(const VoxelGrid& grid, const glm::ivec3& lo, const glm::ivec3& hi,
               const glm::ivec3& cellDims, int words, int cz, std::vector<std::uint64_t>& rows,
               std::vector<LatticeCell>& cells) {
  constexpr int B = VoxelGrid::kBrickSize;
  std::fill(rows.begin(), rows.end(), 0);
  for (int dz = 0; dz < 3; ++dz) {
    const int z = lo.z + 3 * cz + dz;
    if (z > hi.z) break;
    for (int y = lo.y; y <= hi.y; ++y) {
      std::uint64_t* row =
          &rows[(std::size_t(dz) * std::size_t(3 * cellDims.y) + std::size_t(y - lo.y)) *
                std::size_t(words)];
      for (int bx = lo.x / B; bx <= hi.x / B; ++bx) {
        const std::size_t brick = grid.brickIndex({bx, y / B, z / B});
        const VoxelGrid::Brick* b = grid.brickData(brick);
        if (!b && grid.brickUniformFill(brick) == 0) continue;
        const int x0 = std::max(bx * B, lo.x), x1 = std::min(bx * B + B - 1, hi.x);
        const int local = VoxelGrid::voxelInBrick({0, y % B, z % B});
        for (int x = x0; x <= x1; ++x) {
          if (b && b->fill[std::size_t(local + x - bx * B)] == 0) continue;
          const int bit = x - lo.x;
          row[bit >> 6] |= std::uint64_t(1) << (bit & 63);
        }
      }
    }
  }

  for (int cy = 0; cy < cellDims.y; ++cy) {
    for (int cx = 0; cx < cellDims.x; ++cx) {
      std::uint32_t mask = 0;
      const int bit = 3 * cx;
      for (int dz = 0; dz < 3; ++dz) {
        for (int dy = 0; dy < 3; ++dy) {
          const std::uint64_t* row =
              &rows[(std::size_t(dz) * std::size_t(3 * cellDims.y) + std::size_t(3 * cy + dy)) *
                    std::size_t(words)];
          std::uint64_t three = row[bit >> 6] >> (bit & 63);
          if ((bit & 63) > 61 && (bit >> 6) + 1 < words)
            three |= row[(bit >> 6) + 1] << (64 - (bit & 63));
          mask |= std::uint32_t(three & 7u) << (3 * (dy + 3 * dz));
        }
      }
      if (mask != 0) cells.push_back({lo + 3 * glm::ivec3(cx, cy, cz), mask});
    }
  }
}

}  // namespace

bool DynamicProximityHierarchy::buildLatticeFromGrid(const VoxelGrid& grid) {
  glm::ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
  const std::uint64_t occupied = occupiedBounds(grid, lo, hi);
  if (occupied < 2 || occupied >= kNone) return false;  // the voxel-list build handles these
  int keyBits = 0;
  if (!prepareLattice(lo, hi, keyBits)) return false;

  // One layer of cells at a time, in parallel (scanLayer).
  const glm::ivec3 cellDims = (hi - lo) / 3 + 1;
  const int words = (cellDims.x * 3 + 63) / 64;
  std::vector<std::vector<LatticeCell>> layers(std::size_t(cellDims.z));
  tbb::parallel_for(tbb::blocked_range<int>(0, cellDims.z), [&](const tbb::blocked_range<int>& r) {
    std::vector<std::uint64_t> rows(std::size_t(3 * cellDims.y * 3) * std::size_t(words));
    for (int cz = r.begin(); cz < r.end(); ++cz) {
      scanLayer(grid, lo, hi, cellDims, words, cz, rows, layers[std::size_t(cz)]);
    }
  });

  std::size_t cellCount = 0;
  for (const std::vector<LatticeCell>& layer : layers) cellCount += layer.size();
  std::vector<LatticeCell> scanned;
  scanned.reserve(cellCount);
  for (std::vector<LatticeCell>& layer : layers) {
    scanned.insert(scanned.end(), layer.begin(), layer.end());
    std::vector<LatticeCell>().swap(layer);
  }
  std::vector<std::uint64_t> cells(cellCount);
  for (std::size_t i = 0; i < cellCount; ++i) {
    const glm::ivec3 o = scanned[i].corner - lo;
    cells[i] = (keySpread_[0][std::size_t(o.x)] + keySpread_[1][std::size_t(o.y)] +
                keySpread_[2][std::size_t(o.z)]) /
               27;
  }
  const std::vector<std::uint32_t> order =
      sortKeys(cells, std::max(1, keyBits - 4));  // key / 27 < 2^(keyBits - 4)

  Level level0, level1;
  level1.centre.resize(cellCount);
  level1.childBegin.resize(cellCount);
  level1.childEnd.resize(cellCount);
  level1.aliveChildren.resize(cellCount);
  level1.boxMin.resize(cellCount);
  level1.boxMax.resize(cellCount);
  level1.parent.assign(cellCount, kNone);
  level1.alive.assign(cellCount, 1);
  level1.aliveCount = cellCount;
  std::size_t n = 0;
  for (std::size_t p = 0; p < cellCount; ++p) {
    const auto count = std::uint32_t(__builtin_popcount(scanned[order[p]].mask));
    level1.childBegin[p] = std::uint32_t(n);
    level1.childEnd[p] = std::uint32_t(n + count);
    level1.aliveChildren[p] = count;
    maxChildren_ = std::max<std::size_t>(maxChildren_, count);
    n += count;
  }
  level0.digit.resize(n);
  level0.alive.assign(n, 1);
  level0.aliveCount = n;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cellCount, 1 << 12),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t p = r.begin(); p < r.end(); ++p) {
                        const LatticeCell& c = scanned[order[p]];
                        std::uint16_t* digit = &level0.digit[level1.childBegin[p]];
                        for (std::uint32_t m = c.mask; m != 0; m &= m - 1)
                          *digit++ = std::uint16_t(__builtin_ctz(m));
                        glm::ivec3 bMin, bMax;
                        axisRange(c.mask, kCellX0, 1, bMin.x, bMax.x);
                        axisRange(c.mask, kCellY0, 3, bMin.y, bMax.y);
                        axisRange(c.mask, kCellZ0, 9, bMin.z, bMax.z);
                        level1.centre[p] = c.corner + 1;
                        level1.boxMin[p] = c.corner + bMin;
                        level1.boxMax[p] = c.corner + bMax;
                      }
                    });
  levels_.push_back(std::move(level0));
  levels_.push_back(std::move(level1));
  halfWidth_.push_back(1);
  buildUpperLevels(std::move(cells));
  return true;
}

void DynamicProximityHierarchy::buildUpperLevels(std::vector<std::uint64_t> keys) {
  const std::uint64_t xi = std::uint64_t(xi_);
  const std::uint64_t cellsPerParent = xi * xi * xi;
  const glm::ivec3 lo = latticeOriginVoxel_;
  cellKeys_ = keys;
  // Each level from the one below: a run of equal key / xi^3 is one parent cell.
  long long cellEdge = xi_;
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
    std::size_t p = 0;
    for (std::size_t i = 0; i < count;) {
      const std::uint64_t cell = keys[i] / cellsPerParent;
      const std::uint64_t cellEnd = (cell + 1) * cellsPerParent;  // keys of this cell lie below
      glm::ivec3 bMin = below.boxMin[i], bMax = below.boxMax[i];
      std::size_t j = i;
      for (; j < count && keys[j] < cellEnd; ++j) {
        below.parent[j] = std::uint32_t(p);
        bMin = glm::min(bMin, below.boxMin[j]);
        bMax = glm::max(bMax, below.boxMax[j]);
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
    levels_.push_back(std::move(above));
    halfWidth_.push_back((cellEdge - 1) / 2);
  }
  cellKeys_.shrink_to_fit();
  lattice_ = true;
}

}  // namespace osteon::geometry
