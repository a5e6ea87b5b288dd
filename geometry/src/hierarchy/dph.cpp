#include "osteon/geometry/hierarchy/dph.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <sstream>
#include <unordered_map>

#include "dph_internal.h"
#include "osteon/core/error.h"
#include "osteon/core/option_error.h"

namespace osteon::geometry {

using namespace dph_detail;

namespace {

// A new number for every build (copies share theirs), so a kept cache never answers another.
std::uint64_t nextGeneration() {
  static std::atomic<std::uint64_t> builds{0};
  return ++builds;
}

}  // namespace

DynamicProximityHierarchy DynamicProximityHierarchy::build(const std::vector<glm::ivec3>& voxels,
                                                           const DphBuildOptions& options,
                                                           glm::dvec3 originMm,
                                                           double voxelSizeMm) {
  const int xi = options.expansionRatio;
  if (xi < 3 || xi > 15 || xi % 2 == 0) {
    throw OptionError("xi", std::to_string(xi),
                      "the expansion ratio must be odd, from 3 to 15 (cells centred on a voxel)");
  }
  DynamicProximityHierarchy h;
  h.generation_ = nextGeneration();
  h.xi_ = xi;
  h.originMm_ = originMm;
  h.voxelSizeMm_ = voxelSizeMm;
  const std::size_t n = voxels.size();
  if (n >= kNone) throw InputError("hierarchy: more than 2^32 - 1 voxels");
  for (const glm::ivec3& v : voxels) {
    if (!packable(v)) throw InputError("hierarchy: voxel coordinate beyond +-2^20");
  }
  if (n == 0) return h;
  if (options.method == DphBuildMethod::kLattice && h.buildLattice(voxels)) return h;
  DphBuildOptions insertion = options;
  if (options.method == DphBuildMethod::kLattice)
    insertion.shuffle = false;  // too wide a key: the given order
  h.buildInsertion(voxels, insertion);
  return h;
}

DynamicProximityHierarchy DynamicProximityHierarchy::build(const VoxelGrid& grid,
                                                           const DphBuildOptions& options) {
  if (options.method == DphBuildMethod::kLattice && options.expansionRatio == 3) {
    DynamicProximityHierarchy h;
    h.generation_ = nextGeneration();
    h.originMm_ = grid.originMm();
    h.voxelSizeMm_ = grid.voxelSizeMm();
    const glm::ivec3 far = grid.dims() - 1;
    if (packable(far) && h.buildLatticeFromGrid(grid)) return h;
  }
  std::vector<glm::ivec3> occupied;
  occupied.reserve(std::size_t(grid.countVoxels(1)));
  const glm::ivec3 dims = grid.dims();
  constexpr int B = VoxelGrid::kBrickSize;
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    const VoxelGrid::Brick* b = grid.brickData(brick);
    if (!b && grid.brickUniformFill(brick) == 0) continue;
    const glm::ivec3 lo = grid.brickCoord(brick) * B;
    const glm::ivec3 hi = glm::min(lo + B, dims);
    for (int z = lo.z; z < hi.z; ++z)
      for (int y = lo.y; y < hi.y; ++y)
        for (int x = lo.x; x < hi.x; ++x) {
          const glm::ivec3 v(x, y, z);
          if (!b || b->fill[std::size_t(VoxelGrid::voxelInBrick(v - lo))] > 0)
            occupied.push_back(v);
        }
  }
  return build(occupied, options, grid.originMm(), grid.voxelSizeMm());
}

std::uint32_t DynamicProximityHierarchy::root() const {
  if (levels_.empty()) return kNone;
  const Level& top = levels_.back();
  return top.aliveCount > 0 && top.alive[0] ? 0u : kNone;
}

std::uint32_t DynamicProximityHierarchy::parent(int level, std::uint32_t node) const {
  if (level > 0 || !compactVoxels()) return levels_[std::size_t(level)].parent[node];
  const std::vector<std::uint32_t>& begins =
      levels_[1].childBegin;  // ascending in the lattice build
  return std::uint32_t(std::upper_bound(begins.begin(), begins.end(), node) - begins.begin()) - 1;
}

std::uint32_t DynamicProximityHierarchy::findVoxel(const glm::ivec3& voxel,
                                                   std::uint32_t* cellOut) const {
  if (!packable(voxel)) return kNone;
  std::uint32_t node = kNone;
  if (lattice_) {
    std::uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const long long d = (long long)voxel[a] - latticeOriginVoxel_[a];
      if (d < 0 || d >= (long long)keySpread_[a].size()) return kNone;
      key += keySpread_[std::size_t(a)][std::size_t(d)];
    }
    const Level& level0 = levels_[0];
    if (!compactVoxels()) {  // a single voxel: no level 1
      node = level0.centre[0] == voxel ? 0 : kNone;
    } else {
      const std::uint64_t cells = std::uint64_t(xi_) * std::uint64_t(xi_) * std::uint64_t(xi_);
      const auto it = std::lower_bound(cellKeys_.begin(), cellKeys_.end(), key / cells);
      if (it == cellKeys_.end() || *it != key / cells) return kNone;
      const auto cell = std::uint32_t(it - cellKeys_.begin());
      const auto digit = std::uint16_t(key % cells);
      for (std::uint32_t c = levels_[1].childBegin[cell]; c < levels_[1].childEnd[cell];
           ++c) {  // ascending digits
        if (level0.digit[c] == digit) {
          node = c;
          if (cellOut) *cellOut = cell;
          break;
        }
      }
    }
  } else {
    const std::uint64_t key = packVoxel(voxel);
    const auto it = std::lower_bound(voxelKeys_.begin(), voxelKeys_.end(), key);
    if (it != voxelKeys_.end() && *it == key)
      node = voxelNodes_[std::size_t(it - voxelKeys_.begin())];
  }
  if (node == kNone || !levels_[0].alive[node]) return kNone;
  if (cellOut && !compactVoxels()) *cellOut = levels_[0].parent[node];
  return node;
}

bool DynamicProximityHierarchy::removeVoxel(const glm::ivec3& voxel) {
  std::uint32_t cell = kNone;
  std::uint32_t node = findVoxel(voxel, &cell);
  if (node == kNone) return false;
  levels_[0].alive[node] = 0;
  --levels_[0].aliveCount;
  // Walk up while parents are left without children.
  node = cell;
  for (std::size_t L = 1; L < levels_.size(); ++L) {
    Level& lv = levels_[L];
    if (--lv.aliveChildren[node] > 0) break;
    lv.alive[node] = 0;
    --lv.aliveCount;
    node = lv.parent[node];
  }
  return true;
}

namespace {
std::uint64_t newCacheId() {
  static std::atomic<std::uint64_t> ids{0};
  return ++ids;
}
}  // namespace

DphNearCache::DphNearCache() : id_(newCacheId()) {}

DphNearCache::DphNearCache(DphNearCache&& other) noexcept : DphNearCache() {
  *this = std::move(other);
}

DphNearCache& DphNearCache::operator=(DphNearCache&& other) noexcept {
  if (this == &other) return *this;
  owner_ = other.owner_;
  generation_ = other.generation_;
  skinMm_ = other.skinMm_;
  sliceNodes_ = other.sliceNodes_;
  kept_ = std::move(other.kept_);
  next_ = std::move(other.next_);
  slicing_ = other.slicing_;
  nextFits_ = other.nextFits_;
  stack_ = std::move(other.stack_);
  top_ = other.top_;
  walks_ = other.walks_;
  reuses_ = other.reuses_;
  sliced_ = other.sliced_;
  overflows_ = other.overflows_;
  id_ = other.id_;
  travelNm_ = other.travelNm_;
  lastAMm_ = other.lastAMm_;
  lastBMm_ = other.lastBMm_;
  travelled_ = other.travelled_;
  nextKind_ = other.nextKind_;
  // The moved-from cache starts over under a new id: stamps made with the old id now belong
  // to this cache, whose odometer they were read from.
  other.owner_ = nullptr;
  other.kept_ = Answer();
  other.next_ = Answer();
  other.slicing_ = false;
  other.stack_.clear();
  other.top_ = 0;
  other.id_ = newCacheId();
  other.travelNm_ = 0;
  other.travelled_ = false;
  return *this;
}

void DphNearCache::recordTravel(const glm::dvec3& a, const glm::dvec3& b) {
  if (travelled_) {
    const double moved = std::max(glm::length(a - lastAMm_), glm::length(b - lastBMm_));
    if (!(moved < 1e6)) {
      travelNm_ += std::uint64_t(1) << 40;  // a jump (or a non-finite pose): beyond any slack
    } else if (moved > 0.0) {
      travelNm_ += std::uint64_t(std::ceil(moved * 1e6)) +
                   1;  // rounded up, and a nanometre for the rounding
    }
  }
  lastAMm_ = a;
  lastBMm_ = b;
  travelled_ = true;
}

DphNearCache::DphNearCache(double skinMm, std::size_t capacity, std::size_t sliceNodes)
    : skinMm_(skinMm), sliceNodes_(sliceNodes), id_(newCacheId()) {
  if (!(skinMm >= 0.0) || !std::isfinite(skinMm)) {
    throw InputError("query cache skin " + std::to_string(skinMm) +
                     " mm: must be a finite length >= 0");
  }
  kept_.reserve(capacity);
  if (sliceNodes_ > 0) next_.reserve(capacity);
}

void DphNearCache::Answer::reserve(std::size_t capacity) {
  // Sized and written now, so that no page of it is first touched inside a query.
  nodes.resize(capacity);
  centres.resize(capacity);
  nodes.clear();
  centres.clear();
}

void DphNearCache::reserveFor(const DynamicProximityHierarchy& h) {
  if (sliceNodes_ > 0) stack_.assign(h.traversalStackSize(), 0);
}

std::size_t DphNearCache::capacityFor(double lengthMm, double radiusMm, double voxelMm) {
  // Voxel centres within r of the core fill at most the core's volume inflated by half a
  // voxel diagonal (each voxel's cube lies inside it): bound by one voxel.
  const double r = radiusMm / voxelMm + 1.0, len = lengthMm / voxelMm;
  const double count = M_PI * r * r * len + 4.0 / 3.0 * M_PI * r * r * r;
  return std::size_t(std::ceil(count)) + 64;
}

double DphNearCache::moved(const Answer& answer, const glm::dvec3& a, const glm::dvec3& b) {
  return std::max(glm::length(a - answer.aMm), glm::length(b - answer.bMm));
}

bool DphNearCache::covers(const DynamicProximityHierarchy& h, const Answer& answer,
                          const glm::dvec3& a, const glm::dvec3& b, double radiusMm) const {
  if (answer.reachMm < 0.0) return false;
  // Every point of the new segment lies within max(|a - a0|, |b - b0|) of the kept one's
  // (the same interpolation parameter), so the new capsule lies inside the kept one inflated
  // by that much. A relative margin covers the rounding of the walk's distances.
  return moved(answer, a, b) + radiusMm <= answer.reachMm * (1.0 - 1e-9) - 1e-9 * h.voxelSizeMm();
}

std::size_t DynamicProximityHierarchy::traversalStackSize() const {
  // Depth first: at most every child of one node per level waits on the stack.
  return std::size_t(levelCount()) * (maxChildren_ + 1) + 1;
}

void DynamicProximityHierarchy::reserveScratch(DphQueryScratch& scratch) const {
  const std::size_t need = traversalStackSize();
  if (scratch.stack.size() < need) scratch.stack.resize(need);
}

std::string DynamicProximityHierarchy::validate() const {
  std::ostringstream err;
  if (levels_.empty()) return "";
  long long edge = 1;
  for (std::size_t L = 0; L < levels_.size(); ++L) {
    const Level& lv = levels_[L];
    if (halfWidth_[L] != (edge - 1) / 2) {
      err << "level " << L << ": half width " << halfWidth_[L] << ", expected " << (edge - 1) / 2;
      return err.str();
    }
    edge *= xi_;
    const std::size_t alive = std::size_t(std::count(lv.alive.begin(), lv.alive.end(), 1));
    if (alive != lv.aliveCount) {
      err << "level " << L << ": " << alive << " alive nodes but a count of " << lv.aliveCount;
      return err.str();
    }
    for (std::uint32_t i = 0; i < lv.alive.size(); ++i) {
      if (!lv.alive[i]) continue;
      const glm::ivec3 centreI = centre(int(L), i);
      if (L + 1 < levels_.size()) {
        const Level& up = levels_[L + 1];
        const std::uint32_t p = parent(int(L), i);
        if (p >= up.centre.size() || !up.alive[p]) {
          err << "level " << L << " node " << i << ": no alive parent";
          return err.str();
        }
        if (i < up.childBegin[p] || i >= up.childEnd[p]) {
          err << "level " << L << " node " << i << ": outside its parent's child range";
          return err.str();
        }
        if (chebyshev(centreI, up.centre[p]) > halfWidth_[L + 1]) {
          err << "level " << L << " node " << i << ": centre outside its parent's cell";
          return err.str();
        }
        const glm::ivec3 lo = L == 0 ? centreI : lv.boxMin[i];
        const glm::ivec3 hi = L == 0 ? centreI : lv.boxMax[i];
        if (glm::any(glm::lessThan(lo, up.boxMin[p])) ||
            glm::any(glm::greaterThan(hi, up.boxMax[p]))) {
          err << "level " << L << " node " << i << ": not inside its parent's box";
          return err.str();
        }
      } else if (parent(int(L), i) != kNone) {
        err << "top level node " << i << " has a parent";
        return err.str();
      }
      if (L > 0) {
        std::uint32_t children = 0;
        for (std::uint32_t c = lv.childBegin[i]; c < lv.childEnd[i]; ++c) {
          if (parent(int(L) - 1, c) != i) {
            err << "level " << L << " node " << i << ": child " << c << " names another parent";
            return err.str();
          }
          children += levels_[L - 1].alive[c];
        }
        if (children != lv.aliveChildren[i] || children == 0) {
          err << "level " << L << " node " << i << ": " << children << " alive children, count "
              << lv.aliveChildren[i];
          return err.str();
        }
      }
    }
  }
  const Level& top = levels_.back();
  if (top.centre.size() != 1)
    return "top level has " + std::to_string(top.centre.size()) + " nodes";
  if (top.aliveCount != (levels_[0].aliveCount > 0 ? 1u : 0u)) {
    return "root is " + std::string(top.aliveCount ? "alive" : "gone") + " with " +
           std::to_string(levels_[0].aliveCount) + " voxels left";
  }
  for (std::size_t i = 1; i < voxelKeys_.size(); ++i) {
    if (voxelKeys_[i - 1] >= voxelKeys_[i]) return "voxel index is not sorted";
  }
  if (lattice_) {
    if (levels_.size() > 1 && cellKeys_.size() != levels_[1].centre.size())
      return "cell index size is wrong";
    if (compactVoxels() && levels_[0].digit.size() != levels_[0].alive.size())
      return "voxel digits are missing";
    for (std::size_t i = 1; i < cellKeys_.size(); ++i) {
      if (cellKeys_[i - 1] >= cellKeys_[i]) return "cell index is not sorted";
    }
    for (std::uint32_t i = 0; i < levels_[0].alive.size(); ++i) {  // every voxel found where it is
      if (levels_[0].alive[i] && findVoxel(centre(0, i)) != i) {
        return "voxel index does not find level-0 node " + std::to_string(i);
      }
    }
  }
  return "";
}

std::string DynamicProximityHierarchy::validateAgainst(const VoxelGrid& grid) const {
  std::string err = validate();
  if (!err.empty()) return err;
  if (levels_.empty()) {
    return grid.countVoxels(1) == 0 ? "" : "empty hierarchy over a grid with bone";
  }
  const Level& level0 = levels_[0];
  for (std::uint32_t i = 0; i < level0.alive.size(); ++i) {
    if (level0.alive[i] && grid.fill(centre(0, i)) == 0) {
      const glm::ivec3 v = centre(0, i);
      return "voxel (" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
             std::to_string(v.z) + ") is in the hierarchy but empty in the grid";
    }
  }
  const std::uint64_t occupied = grid.countVoxels(1);
  if (occupied != level0.aliveCount) {
    return "grid has " + std::to_string(occupied) + " occupied voxels, hierarchy " +
           std::to_string(level0.aliveCount);
  }
  return "";
}

std::size_t DynamicProximityHierarchy::memoryBytes() const {
  std::size_t bytes = sizeof(*this) + voxelKeys_.capacity() * sizeof(std::uint64_t) +
                      voxelNodes_.capacity() * sizeof(std::uint32_t) +
                      cellKeys_.capacity() * sizeof(std::uint64_t);
  for (const auto& spread : keySpread_) bytes += spread.capacity() * sizeof(std::uint64_t);
  for (const Level& lv : levels_) {
    bytes += lv.centre.capacity() * sizeof(glm::ivec3) +
             (lv.parent.capacity() + lv.childBegin.capacity() + lv.childEnd.capacity() +
              lv.aliveChildren.capacity()) *
                 sizeof(std::uint32_t) +
             (lv.boxMin.capacity() + lv.boxMax.capacity()) * sizeof(glm::ivec3) +
             lv.alive.capacity() + lv.digit.capacity() * sizeof(std::uint16_t);
  }
  bytes += digitOffset_.capacity() * sizeof(glm::ivec3);
  return bytes;
}

}  // namespace osteon::geometry
