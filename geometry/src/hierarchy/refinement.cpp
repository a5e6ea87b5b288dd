#include "osteon/geometry/hierarchy/refinement.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "osteon/core/assert.h"
#include "osteon/core/error.h"
#include "sub_fill.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace osteon::geometry {

namespace {

std::size_t powerOfTwoAtLeast(std::size_t n) {
  std::size_t p = 1;
  while (p < n) p <<= 1;
  return p;
}

std::size_t slotOf(std::uint64_t key, std::size_t tableSize) {
  return std::size_t((key * 0x9E3779B97F4A7C15ull) >> 17) & (tableSize - 1);
}

}  // namespace

RefinedVoxels::RefinedVoxels(VoxelGrid& grid, DynamicProximityHierarchy& hierarchy,
                             const FineFillSource* source, const RefinementOptions& options)
    : grid_(&grid),
      hierarchy_(&hierarchy),
      source_(source),
      depth_(options.depth),
      marginMm_(options.marginMm < 0.0
                    ? grid.voxelSizeMm() / double(1 << std::max(options.depth, 0))
                    : options.marginMm),
      timeoutS_(options.timeoutS) {
  if (options.depth < 0 || options.depth > kMaxRefineDepth) {
    throw InputError("RefinementOptions::depth " + std::to_string(options.depth) +
                     ": must be 0, 1 or 2");
  }
  if (!std::isfinite(options.timeoutS) || options.timeoutS <= 0.0) {
    std::ostringstream s;
    s << "RefinementOptions::timeoutS " << options.timeoutS
      << ": must be a positive number of seconds";
    throw InputError(s.str());
  }
  if (!std::isfinite(marginMm_)) throw InputError("refinement margin must be finite");
  if (options.capacity == 0 || options.capacity > (1u << 24)) {
    throw InputError("RefinementOptions::capacity " + std::to_string(options.capacity) +
                     ": must be 1 .. 2^24 voxels");
  }
  cells_.resize(options.capacity);
  freeCells_.resize(options.capacity);
  for (std::size_t i = 0; i < options.capacity; ++i) {
    freeCells_[i] = std::uint32_t(options.capacity - 1 - i);
  }
  freeTop_ = options.capacity;
  activeList_.resize(options.capacity);
  activeSlot_.resize(options.capacity);
  const std::size_t tableSize = powerOfTwoAtLeast(2 * options.capacity);
  tableKeys_.assign(tableSize, 0);
  tableCells_.assign(tableSize, kNoCell);
  masks_.assign(powerOfTwoAtLeast(2 * std::max<std::size_t>(options.maskCapacity, 1)),
                Mask{0, 0, 0});
  // Grow the traversal stack now, not in the loop.
  hierarchy.forEachVoxelInSphere(glm::dvec3(0.0), 0.0, scratch_, [](const glm::ivec3&) {});
}

std::uint64_t RefinedVoxels::keyOf(const glm::ivec3& v) const {
  const glm::ivec3 d = grid_->dims();
  return 1 + std::uint64_t(v.x) +
         std::uint64_t(d.x) * (std::uint64_t(v.y) + std::uint64_t(d.y) * std::uint64_t(v.z));
}

std::uint32_t RefinedVoxels::findCell(const glm::ivec3& v) const {
  if (active_ == 0 || !grid_->inBounds(v)) return kNoCell;
  const std::uint64_t key = keyOf(v);
  for (std::size_t s = slotOf(key, tableKeys_.size());; s = (s + 1) & (tableKeys_.size() - 1)) {
    if (tableKeys_[s] == key) return tableCells_[s];
    if (tableKeys_[s] == 0) return kNoCell;
  }
}

void RefinedVoxels::insertCell(std::uint64_t key, std::uint32_t cell) {
  std::size_t s = slotOf(key, tableKeys_.size());
  while (tableKeys_[s] != 0) s = (s + 1) & (tableKeys_.size() - 1);
  tableKeys_[s] = key;
  tableCells_[s] = cell;
}

void RefinedVoxels::eraseCell(std::uint64_t key) {
  const std::size_t mask = tableKeys_.size() - 1;
  std::size_t hole = slotOf(key, tableKeys_.size());
  while (tableKeys_[hole] != key) hole = (hole + 1) & mask;
  // Backward-shift deletion keeps every probe chain unbroken without tombstones.
  for (std::size_t s = (hole + 1) & mask; tableKeys_[s] != 0; s = (s + 1) & mask) {
    const std::size_t home = slotOf(tableKeys_[s], tableKeys_.size());
    if (((s - home) & mask) >= ((s - hole) & mask)) {
      tableKeys_[hole] = tableKeys_[s];
      tableCells_[hole] = tableCells_[s];
      hole = s;
    }
  }
  tableKeys_[hole] = 0;
  tableCells_[hole] = kNoCell;
}

RefinedVoxels::Mask* RefinedVoxels::findMask(std::uint64_t key) {
  for (std::size_t s = slotOf(key, masks_.size());; s = (s + 1) & (masks_.size() - 1)) {
    if (masks_[s].key == key) return &masks_[s];
    if (masks_[s].key == 0) return nullptr;
  }
}

RefinedVoxels::Mask* RefinedVoxels::insertMask(std::uint64_t key, Fill firstFill) {
  if (Mask* m = findMask(key)) return m;
  if (masksUsed_ * 2 >= masks_.size()) {
    ++maskOverflows_;
    return nullptr;
  }
  std::size_t s = slotOf(key, masks_.size());
  while (masks_[s].key != 0) s = (s + 1) & (masks_.size() - 1);
  masks_[s] = Mask{key, 0, firstFill};
  ++masksUsed_;
  return &masks_[s];
}

void RefinedVoxels::baseSubFill(const glm::ivec3& voxel, Fill firstFill,
                                std::array<Fill, kSubVoxels>& out) const {
  if (firstFill == kFillFull) {
    out.fill(detail::kSubFull);
    return;
  }
  std::array<std::uint8_t, kSubVoxels> sampled;
  Fill sampledFill = 0;
  if (source_ && source_->find(voxel, sampled, sampledFill)) {
    // The source already fitted its samples to the voxelized fill; refit only if it differs.
    if (sampledFill == firstFill) {
      std::copy(sampled.begin(), sampled.end(), out.begin());
    } else {
      detail::fitToTotal(sampled, firstFill, out);
    }
  } else {
    detail::distributeExactly(nullptr, firstFill, out);
  }
}

void RefinedVoxels::createCell(const glm::ivec3& voxel, double nowS) {
  if (freeTop_ == 0) {
    ++poolExhausted_;
    return;
  }
  const Fill parentFill = grid_->fill(voxel);
  const Density parentDensity = grid_->density(voxel);
  const std::uint64_t key = keyOf(voxel);
  const Mask* mask = findMask(key);

  // Level -2 fills as the voxel was first refined, minus what was removed since.
  std::array<Fill, kSubVoxels> fine;
  baseSubFill(voxel, mask ? mask->firstFill : parentFill, fine);
  unsigned sum = 0;
  for (int i = 0; i < kSubVoxels; ++i) {
    if (mask && (mask->removed >> i & 1u)) fine[std::size_t(i)] = 0;
    sum += fine[std::size_t(i)];
  }
  if (sum != parentFill) {
    // The parent changed in a way no mask recorded (a full mask table): keep the volume
    // exact and the shape as close as the remaining sub-voxels allow.
    std::array<std::uint8_t, kSubVoxels> weights;
    for (int i = 0; i < kSubVoxels; ++i) {
      weights[std::size_t(i)] = std::uint8_t(std::min<unsigned>(fine[std::size_t(i)], 255u));
    }
    detail::distributeExactly(&weights, parentFill, fine);
  }

  const std::uint32_t cell = freeCells_[--freeTop_];
  Cell& c = cells_[cell];
  c.voxel = voxel;
  c.lastNearS = nowS;
  c.fill.fill(0);
  c.density.fill(0);  // entries past 8^depth stay 0
  const int n = 1 << depth_;
  if (n == kSubPerEdge) {
    c.fill = fine;
  } else {
    const int merge = kSubPerEdge / n;  // level -2 sub-voxels per edge of one sample
    for (int z = 0; z < kSubPerEdge; ++z)
      for (int y = 0; y < kSubPerEdge; ++y)
        for (int x = 0; x < kSubPerEdge; ++x) {
          const std::size_t i = std::size_t((x / merge) + n * ((y / merge) + n * (z / merge)));
          c.fill[i] = Fill(c.fill[i] + fine[std::size_t(x + kSubPerEdge * (y + kSubPerEdge * z))]);
        }
  }
  c.occupied = 0;
  c.slackSite = 0;
  for (int i = 0; i < n * n * n; ++i) {
    c.density[std::size_t(i)] = c.fill[std::size_t(i)] > 0 ? parentDensity : Density(0);
    if (c.fill[std::size_t(i)] > 0) c.occupied |= std::uint64_t(1) << i;
  }
  insertCell(key, cell);
  activeSlot_[cell] = std::uint32_t(active_);
  activeList_[active_++] = cell;
}

void RefinedVoxels::releaseCell(std::uint32_t cell) {
  Cell& c = cells_[cell];
  const int count = 1 << (3 * depth_);
  // The parent keeps the summed fill (already in the grid) and its sub-voxels' mean density.
  long long densitySum = 0;
  int withBone = 0;
  for (int i = 0; i < count; ++i) {
    if (c.fill[std::size_t(i)] == 0) continue;
    densitySum += c.density[std::size_t(i)];
    ++withBone;
  }
  if (withBone > 0) {
    const auto mean = Density((densitySum + withBone - 1) / withBone);  // rounded up: d stays >= 1
    if (grid_->density(c.voxel) != mean) grid_->set(c.voxel, grid_->fill(c.voxel), mean);
  }
  eraseCell(keyOf(c.voxel));
  const std::uint32_t slot = activeSlot_[cell];
  const std::uint32_t last = activeList_[--active_];
  activeList_[slot] = last;
  activeSlot_[last] = slot;
  OSTEON_ASSERT(freeTop_ < freeCells_.size(), "a cell goes back to the pool once");
  freeCells_[freeTop_++] = cell;
}

int RefinedVoxels::refineAround(const glm::dvec3& toolCentreMm, double outerRadiusMm, double nowS,
                                DphNearCache* cache) {
  if (depth_ == 0) return 0;
  lastRefineS_ = nowS;
  const double vs = grid_->voxelSizeMm();
  const double reachMm = outerRadiusMm + marginMm_;
  int created = 0;
  // Voxels whose cube comes within reach of the tool centre: the centre test widened by half
  // a voxel diagonal, then the exact point-to-cube distance.
  hierarchy_->forEachVoxelInSphere(
      toolCentreMm, refineReachMm(outerRadiusMm), scratch_, cache, [&](const glm::ivec3& v) {
        const glm::dvec3 lo = grid_->worldFromGrid(glm::dvec3(v));
        const glm::dvec3 d =
            glm::max(glm::max(lo - toolCentreMm, toolCentreMm - (lo + vs)), glm::dvec3(0.0));
        if (glm::dot(d, d) > reachMm * reachMm) return;
        const std::uint32_t cell = findCell(v);
        if (cell != kNoCell) {
          cells_[cell].lastNearS = nowS;
        } else if (freeTop_ > 0) {
          createCell(v, nowS);
          ++created;
        } else {
          ++poolExhausted_;
        }
      });
  return created;
}

int RefinedVoxels::refineNearSegment(const glm::dvec3& aMm, const glm::dvec3& bMm,
                                     double outerRadiusMm, double nowS, DphNearCache* cache,
                                     std::size_t budget, int& deferred) {
  deferred = 0;
  if (depth_ == 0) return 0;
  lastRefineS_ = nowS;
  int created = 0;
  const auto visit = [&](const glm::ivec3& v) {
    const std::uint32_t cell = findCell(v);
    if (cell != kNoCell) {
      cells_[cell].lastNearS = nowS;
    } else if (std::size_t(created) >= budget) {
      ++deferred;  // the walk's fixed order: a later call refines these first
    } else if (freeTop_ > 0) {
      createCell(v, nowS);
      ++created;
    } else {
      ++poolExhausted_;
    }
  };
  const double reachMm = segmentRefineReachMm(outerRadiusMm);
  if (aMm == bMm) {
    hierarchy_->forEachVoxelInSphere(aMm, reachMm, scratch_, cache, visit);
  } else {
    hierarchy_->forEachVoxelInCapsule(aMm, bMm, reachMm, scratch_, cache, visit);
  }
  return created;
}

int RefinedVoxels::expire(double nowS) {
  int expired = 0;
  for (std::size_t i = active_; i-- > 0;) {
    const std::uint32_t cell = activeList_[i];
    if (nowS - cells_[cell].lastNearS > timeoutS_) {
      releaseCell(cell);
      ++expired;
    }
  }
  return expired;
}

int RefinedVoxels::expireAll() {
  const int n = int(active_);
  while (active_ > 0) releaseCell(activeList_[active_ - 1]);
  return n;
}

namespace {

// How far the shell can move before a sample with bone enters it: the nearest such sample
// beyond the outer layer or within the inner one (squared distances; none: infinity).
template <typename Terms>
double shellSlackMm(double minAbove2, double maxBelow2, const Terms& terms) {
  const double above = minAbove2 < std::numeric_limits<double>::infinity()
                           ? std::sqrt(minAbove2) - terms.outerMm
                           : std::numeric_limits<double>::infinity();
  const double below = maxBelow2 >= 0.0 ? terms.innerMm - std::sqrt(maxBelow2)
                                        : std::numeric_limits<double>::infinity();
  return std::min(above, below);
}

// shellSamplesOf sample by sample, over the lattice it computed: a single sample per cell, or a
// build without SSE2. Templates over RefinedVoxels' private shell types, which it receives from
// its member.
template <typename Cell, typename Terms, typename Hits>
void scalarShellSamples(const Cell& cell, int n, const std::array<double, 4>& cx,
                        const std::array<double, 4>& cy, const std::array<double, 4>& cz,
                        const std::array<double, 4>& px, const std::array<double, 4>& py,
                        const std::array<double, 4>& pz, const Terms& terms, Hits& hits,
                        double& minAbove2, double& maxBelow2) {
  const auto keep = [&](int i, double tx, double ty, double tz) {
    hits.index[std::size_t(hits.count)] = std::uint8_t(i);
    hits.toCore[std::size_t(hits.count)] = {tx, ty, tz};
    ++hits.count;
  };
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const int i = x + n * (y + n * z);
        if (cell.fill[std::size_t(i)] == 0) continue;
        double t = ((px[std::size_t(x)] + py[std::size_t(y)]) + pz[std::size_t(z)]) * terms.invLen2;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        const double tx = (terms.a.x + t * terms.ab.x) - cx[std::size_t(x)];
        const double ty = (terms.a.y + t * terms.ab.y) - cy[std::size_t(y)];
        const double tz = (terms.a.z + t * terms.ab.z) - cz[std::size_t(z)];
        const double d2 = (tx * tx + ty * ty) + tz * tz;
        if (d2 > terms.inner2 && d2 <= terms.outer2) keep(i, tx, ty, tz);
        if (d2 > terms.outer2) minAbove2 = std::min(minAbove2, d2);
        if (d2 <= terms.inner2) maxBelow2 = std::max(maxBelow2, d2);
      }
}

#if defined(__SSE2__)
// The vector loop's slack lanes into its scalars.
[[gnu::always_inline]] inline void lanesToSlack(__m128d minAboveV, __m128d maxBelowV,
                                                double& minAbove2, double& maxBelow2) {
  alignas(16) double lo[2], hi[2];
  _mm_store_pd(lo, minAboveV);
  _mm_store_pd(hi, maxBelowV);
  minAbove2 = std::min(lo[0], lo[1]);
  maxBelow2 = std::max(hi[0], hi[1]);
}

// Samples i and i + 1 kept as `in` says (bit 0, bit 1), with their offsets to the core.
template <typename Hits>
[[gnu::always_inline]] inline void keepPair(int in, int i, __m128d tx, __m128d ty, __m128d tz,
                                            Hits& hits) {
  alignas(16) double vx[2], vy[2], vz[2];
  _mm_store_pd(vx, tx);
  _mm_store_pd(vy, ty);
  _mm_store_pd(vz, tz);
  for (int k = 0; k < 2; ++k) {
    if ((in >> k & 1) == 0) continue;
    hits.index[std::size_t(hits.count)] = std::uint8_t(i + k);
    hits.toCore[std::size_t(hits.count)] = {vx[k], vy[k], vz[k]};
    ++hits.count;
  }
}
#endif

}  // namespace

// The samples of one refined cell within the shell, by distance to the segment a-b.
// The lattice's per-axis terms are centre coordinates and their parts of (centre - a) . ab,
// summed in the order glm::dot sums them, so every distance here equals the one glm computes
// for the sample's centre to the bit (the same samples, whatever the caller checks them
// against). Most of a haptic step is this loop. Around a point (the drill's tip, a burr) every
// distance is ((a.x - x)^2 + (a.y - y)^2) + (a.z - z)^2, and rounded addition is monotonic, so a
// row's smallest and largest squared x term bound all its distances exactly: rows wholly beyond
// the outer layer or within the inner one are skipped without testing their samples. For the
// slack: the smallest squared distance among samples beyond the outer layer, the largest among
// those within the inner one (samples without bone do not count).
double RefinedVoxels::shellSamplesOf(const Cell& cell, const glm::dvec3& cornerMm,
                                     const ShellTerms& terms, ShellHits& hits,
                                     bool wantSlack) const {
  hits.count = 0;
  double minAbove2 = std::numeric_limits<double>::infinity(),
         maxBelow2 = -std::numeric_limits<double>::infinity();
  const auto slack = [&] {
    return wantSlack && hits.count == 0 ? shellSlackMm(minAbove2, maxBelow2, terms) : 0.0;
  };
  if (cell.occupied == 0) return slack();  // drilled through: no sample left
  const int n = 1 << depth_;
  const double sub = grid_->voxelSizeMm() / double(n);
  std::array<double, 4> cx, cy, cz, px, py, pz;
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 c = cornerMm + (double(k) + 0.5) * sub;
    cx[std::size_t(k)] = c.x;
    cy[std::size_t(k)] = c.y;
    cz[std::size_t(k)] = c.z;
    px[std::size_t(k)] = (c.x - terms.a.x) * terms.ab.x;
    py[std::size_t(k)] = (c.y - terms.a.y) * terms.ab.y;
    pz[std::size_t(k)] = (c.z - terms.a.z) * terms.ab.z;
  }
  const bool point = !(terms.invLen2 > 0.0);
  std::array<double, 4> dy2{}, dz2{};
  double minX2 = 0.0, maxX2 = 0.0;
  if (point) {
    for (int k = 0; k < n; ++k) {
      const double dx = terms.a.x - cx[std::size_t(k)];
      const double x2 = dx * dx;
      minX2 = k == 0 ? x2 : std::min(minX2, x2);
      maxX2 = k == 0 ? x2 : std::max(maxX2, x2);
      const double dy = terms.a.y - cy[std::size_t(k)], dz = terms.a.z - cz[std::size_t(k)];
      dy2[std::size_t(k)] = dy * dy;
      dz2[std::size_t(k)] = dz * dz;
    }
  }
#if defined(__SSE2__)
  const auto rowOutside = [&](int y, int z) {
    if (!point) return false;
    const double lo = (minX2 + dy2[std::size_t(y)]) + dz2[std::size_t(z)];
    const double hi = (maxX2 + dy2[std::size_t(y)]) + dz2[std::size_t(z)];
    return lo > terms.outer2 || hi <= terms.inner2;
  };
  if (n >= 2) {
    const __m128d ax = _mm_set1_pd(terms.a.x), ay = _mm_set1_pd(terms.a.y),
                  az = _mm_set1_pd(terms.a.z);
    const __m128d bx = _mm_set1_pd(terms.ab.x), by = _mm_set1_pd(terms.ab.y),
                  bz = _mm_set1_pd(terms.ab.z);
    const __m128d inv = _mm_set1_pd(terms.invLen2), zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
    const __m128d inner2 = _mm_set1_pd(terms.inner2), outer2 = _mm_set1_pd(terms.outer2);
    const __m128d inf = _mm_set1_pd(std::numeric_limits<double>::infinity());
    const __m128d negInf = _mm_set1_pd(-std::numeric_limits<double>::infinity());
    __m128d minAboveV = inf, maxBelowV = negInf;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y) {
        const __m128d pyv = _mm_set1_pd(py[std::size_t(y)]), pzv = _mm_set1_pd(pz[std::size_t(z)]);
        if (rowOutside(y, z)) continue;
        const int row = n * (y + n * z);
        const unsigned rowBits = unsigned(cell.occupied >> row) & ((1u << n) - 1u);
        if (rowBits == 0) continue;
        const __m128d cyv = _mm_set1_pd(cy[std::size_t(y)]), czv = _mm_set1_pd(cz[std::size_t(z)]);
        for (int x = 0; x < n; x += 2) {
          const int i = row + x;
          const bool f0 = ((rowBits >> x) & 1u) != 0, f1 = ((rowBits >> (x + 1)) & 1u) != 0;
          if (!f0 && !f1) continue;
          const __m128d dot = _mm_add_pd(_mm_add_pd(_mm_loadu_pd(&px[std::size_t(x)]), pyv), pzv);
          const __m128d t = _mm_min_pd(_mm_max_pd(_mm_mul_pd(dot, inv), zero), one);
          const __m128d tx =
              _mm_sub_pd(_mm_add_pd(ax, _mm_mul_pd(t, bx)), _mm_loadu_pd(&cx[std::size_t(x)]));
          const __m128d ty = _mm_sub_pd(_mm_add_pd(ay, _mm_mul_pd(t, by)), cyv);
          const __m128d tz = _mm_sub_pd(_mm_add_pd(az, _mm_mul_pd(t, bz)), czv);
          const __m128d d2 =
              _mm_add_pd(_mm_add_pd(_mm_mul_pd(tx, tx), _mm_mul_pd(ty, ty)), _mm_mul_pd(tz, tz));
          const int in =
              _mm_movemask_pd(_mm_and_pd(_mm_cmpgt_pd(d2, inner2), _mm_cmple_pd(d2, outer2))) &
              (int(f0) | (int(f1) << 1));
          if (wantSlack) {
            const __m128d bone = _mm_castsi128_pd(_mm_set_epi64x(f1 ? -1 : 0, f0 ? -1 : 0));
            const __m128d above = _mm_and_pd(_mm_cmpgt_pd(d2, outer2), bone);
            const __m128d below = _mm_and_pd(_mm_cmple_pd(d2, inner2), bone);
            minAboveV =
                _mm_min_pd(minAboveV, _mm_or_pd(_mm_and_pd(above, d2), _mm_andnot_pd(above, inf)));
            maxBelowV = _mm_max_pd(maxBelowV,
                                   _mm_or_pd(_mm_and_pd(below, d2), _mm_andnot_pd(below, negInf)));
          }
          if (in == 0) continue;
          keepPair(in, i, tx, ty, tz, hits);
        }
      }
    if (wantSlack) lanesToSlack(minAboveV, maxBelowV, minAbove2, maxBelow2);
    return slack();
  }
#endif
  scalarShellSamples(cell, n, cx, cy, cz, px, py, pz, terms, hits, minAbove2, maxBelow2);
  return slack();
}

std::size_t RefinedVoxels::memoryBytes() const {
  return cells_.capacity() * sizeof(Cell) +
         (freeCells_.capacity() + activeList_.capacity() + activeSlot_.capacity() +
          tableCells_.capacity()) *
             sizeof(std::uint32_t) +
         tableKeys_.capacity() * sizeof(std::uint64_t) + masks_.capacity() * sizeof(Mask);
}

}  // namespace osteon::geometry
