// A refined voxel's samples as the drilling step opens, settles and removes them, and the
// queries and accessors around the refined set (refinement.cpp keeps the cell table and the
// shell test).
#include <algorithm>
#include <cmath>
#include <emmintrin.h>
#include <limits>
#include <sstream>

#include "osteon/core/assert.h"
#include "osteon/core/error.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "sub_fill.h"

namespace osteon::geometry {

bool RefinedVoxels::openBlock(const glm::ivec3& voxel, SampleBlock& block) {
  const std::uint32_t cell = active_ == 0 ? kNoCell : findCell(voxel);
  if (cell == kNoCell) return false;
  Cell& c = cells_[cell];
  block.voxel = voxel;
  block.cornerMm = grid_->worldFromGrid(glm::dvec3(voxel));
  block.perEdge = 1 << depth_;
  block.sampleMm = grid_->voxelSizeMm() / block.perEdge;
  block.fill = c.fill.data();
  block.density = c.density.data();
  block.occupied = &c.occupied;
  block.cell = cell;
  return true;
}

bool RefinedVoxels::settleBlock(const SampleBlock& block, std::uint64_t removed,
                                std::uint64_t removedFill) {
  if (removed == 0) return false;
  // The level -2 sub-voxels the removed samples cover.
  const int n = block.perEdge, merge = kSubPerEdge / n;
  std::uint64_t removedBits = 0;
  for (int i = 0; i < n * n * n; ++i) {
    if (!((removed >> i) & 1)) continue;
    const int x = i % n, y = (i / n) % n, z = i / (n * n);
    for (int fz = z * merge; fz < (z + 1) * merge; ++fz)
      for (int fy = y * merge; fy < (y + 1) * merge; ++fy)
        for (int fx = x * merge; fx < (x + 1) * merge; ++fx) {
          removedBits |= std::uint64_t(1) << (fx + kSubPerEdge * (fy + kSubPerEdge * fz));
        }
  }
  // The grid's parent stays the exact sum of its sub-voxels.
  const Fill before = grid_->fill(block.voxel);
  const Fill after = Fill(before - removedFill);
  if (after == 0) {
    grid_->set(block.voxel, 0, 0);
    hierarchy_->removeVoxel(block.voxel);
    releaseCell(block.cell);
    return true;
  }
  grid_->set(block.voxel, after, grid_->density(block.voxel));
  // Remember what went, so a later refinement of this voxel cannot bring it back. At the
  // first removal ever in a voxel, `before` is the fill its sub-voxels were built from.
  if (Mask* mask = insertMask(keyOf(block.voxel), before)) mask->removed |= removedBits;
  return false;
}

void RefinedVoxels::setDensity(const glm::ivec3& voxel, Density density) {
  grid_->set(voxel, grid_->fill(voxel), density);
}

void RefinedVoxels::removeVoxel(const glm::ivec3& voxel) {
  grid_->set(voxel, 0, 0);
  hierarchy_->removeVoxel(voxel);
}

bool RefinedVoxels::collectVoxels(const glm::dvec3& aMm, const glm::dvec3& bMm, double reachMm,
                                  DphNearCache* cache, std::vector<glm::ivec3>& out) {
  bool overflowed = false;
  const auto collect = [&](const glm::ivec3& v) {
    if (out.size() < out.capacity()) {
      out.push_back(v);
    } else {
      overflowed = true;
    }
  };
  if (aMm == bMm) {
    hierarchy_->forEachVoxelInSphere(aMm, reachMm, scratch_, cache, collect);
  } else {
    hierarchy_->forEachVoxelInCapsule(aMm, bMm, reachMm, scratch_, cache, collect);
  }
  return !overflowed;
}

bool RefinedVoxels::SphereAxes::build(const VoxelGrid& grid, const glm::dvec3& pointMm,
                                      double reachMm) {
  const double vs = grid.voxelSizeMm();
  const double r = reachMm / vs;
  if (!(r >= 0.0) || !(r < 0.5 * kMaxSize - 2.0)) return false;
  for (int k = 0; k < 3; ++k) {
    const double g = (pointMm[k] - grid.originMm()[k]) / vs - 0.5;
    if (!(std::abs(g) < 1e9)) return false;
    lo[k] = int(std::floor(g - r)) - 1;
    size[k] = unsigned(int(std::ceil(g + r)) + 1 - lo[k] + 1);
    for (unsigned i = 0; i < size[k]; ++i) {
      glm::ivec3 v(0);
      v[k] = lo[k] + int(i);
      const double c = grid.voxelCentreMm(v)[k];
      const double d = pointMm[k] - c;
      centre[k][i] = c;
      toCore[k][i] = d;
      sq[k][i] = d * d;
    }
  }
  return true;
}

double RefinedVoxels::cutReachMm(double radiusMm) const {
  // The voxels whose centre lies within the cut's radius of its segment (a sphere's of its
  // centre), widened by half a voxel diagonal where voxels may be refined, and by a hair:
  // the query measures in grid units and contains() in millimetres, and a centre exactly on
  // the cut's surface must not be lost to the two roundings disagreeing.
  const double vs = grid_->voxelSizeMm();
  return radiusMm + (depth_ > 0 ? 0.5 * std::sqrt(3.0) * vs : 0.0) + 1e-6 * vs;
}

DphNearCache RefinedVoxels::makeNearCache(double lengthMm, double reachMm, double skinMm,
                                          std::size_t sliceNodes) const {
  DphNearCache cache(skinMm,
                     DphNearCache::capacityFor(lengthMm, reachMm + skinMm, grid_->voxelSizeMm()),
                     sliceNodes);
  cache.reserveFor(*hierarchy_);
  return cache;
}

std::vector<glm::ivec3> RefinedVoxels::refinedVoxels() const {
  std::vector<glm::ivec3> out;
  out.reserve(active_);
  for (std::size_t i = 0; i < active_; ++i) out.push_back(cells_[activeList_[i]].voxel);
  return out;
}

bool RefinedVoxels::subFill(const glm::ivec3& voxel, std::array<Fill, kSubVoxels>& fill,
                            std::array<Density, kSubVoxels>& density) const {
  const std::uint32_t cell = findCell(voxel);
  if (cell == kNoCell) return false;
  fill = cells_[cell].fill;
  density = cells_[cell].density;
  return true;
}

std::size_t RefinedVoxels::bytesInUse() const {
  return active_ * sizeof(Cell) + masksUsed_ * sizeof(Mask);
}

}  // namespace osteon::geometry
