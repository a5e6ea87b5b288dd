#include "osteon/simulation/removal.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace osteon::simulation {

using geometry::Density;
using geometry::Fill;

MaterialRemoval::MaterialRemoval(geometry::RefinedVoxels& voxels, std::size_t cutVoxels)
    : voxels_(&voxels) {
  found_.reserve(cutVoxels);
}

RemovalResult MaterialRemoval::removeFromBlock(const geometry::RefinedVoxels::SampleBlock& block,
                                               const CutVolume& volume, int decrement) {
  RemovalResult result;
  const int n = block.perEdge;
  const double sub = block.sampleMm;
  const glm::dvec3 corner = block.cornerMm;
  std::uint64_t removed = 0;
  // A sphere (the drill's tip, the burr): contains() measures p - a, whose squared length
  // splits into per-axis terms summed in glm::dot's order, so this is the same test to the
  // bit at two additions per sample.
  const glm::dvec3 ab = volume.bMm - volume.aMm;
  const bool sphere = !(glm::dot(ab, ab) > 0.0);
  std::array<double, 4> dx2{}, dy2{}, dz2{};
  for (int k = 0; sphere && k < n; ++k) {
    const glm::dvec3 d = corner + (double(k) + 0.5) * sub - volume.aMm;
    dx2[std::size_t(k)] = d.x * d.x;
    dy2[std::size_t(k)] = d.y * d.y;
    dz2[std::size_t(k)] = d.z * d.z;
  }
  const double r2 = volume.radiusMm * volume.radiusMm;
  // A row whose nearest sample is beyond the sphere has none inside (rounded addition is
  // monotonic, so the bound is exact).
  const double minX2 = *std::min_element(dx2.begin(), dx2.begin() + n);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y) {
      if (sphere && (minX2 + dy2[std::size_t(y)]) + dz2[std::size_t(z)] > r2) continue;
      if (((*block.occupied >> (n * (y + n * z))) & ((std::uint64_t(1) << n) - 1)) == 0) continue;
      for (int x = 0; x < n; ++x) {
        const std::size_t i = std::size_t(x + n * (y + n * z));
        if (block.fill[i] == 0) continue;
        if (sphere ? !((dx2[std::size_t(x)] + dy2[std::size_t(y)]) + dz2[std::size_t(z)] <= r2)
                   : !volume.contains(corner + (glm::dvec3(x, y, z) + 0.5) * sub)) {
          continue;
        }
        block.density[i] = Density(std::max(int(block.density[i]) - decrement, 0));
        if (block.density[i] > 0) {
          ++result.samplesDecremented;
          continue;
        }
        result.removedFill += block.fill[i];
        ++result.samplesRemoved;
        block.fill[i] = 0;
        *block.occupied &= ~(std::uint64_t(1) << i);
        removed |= std::uint64_t(1) << i;
      }
    }
  if (voxels_->settleBlock(block, removed, result.removedFill)) ++result.voxelsEmptied;
  return result;
}

RemovalResult MaterialRemoval::removeIn(const CutVolume& volume, int decrement,
                                        geometry::DphNearCache* cache) {
  RemovalResult total;
  const geometry::VoxelGrid& grid = voxels_->grid();
  const double vs = grid.voxelSizeMm();
  // Collect first: removal edits the hierarchy the query walks.
  found_.clear();
  const bool fitted = voxels_->collectVoxels(volume.aMm, volume.bMm,
                                             voxels_->cutReachMm(volume.radiusMm), cache, found_);
  cutOverflows_ += fitted ? 0 : 1;
  // A refined voxel whose centre lies beyond the cut by more than half its diagonal has no
  // sample inside: it is not opened (64 failing tests).
  const CutVolume widened{volume.aMm, volume.bMm, volume.radiusMm + 0.5 * std::sqrt(3.0) * vs,
                          false};
  geometry::RefinedVoxels::SampleBlock block;
  for (const glm::ivec3& v : found_) {
    if (voxels_->openBlock(v, block)) {
      if (!widened.contains(grid.voxelCentreMm(v))) continue;
      const RemovalResult r = removeFromBlock(block, volume, decrement);
      total.removedFill += r.removedFill;
      total.samplesRemoved += r.samplesRemoved;
      total.samplesDecremented += r.samplesDecremented;
      total.voxelsEmptied += r.voxelsEmptied;
      continue;
    }
    if (!volume.contains(grid.voxelCentreMm(v))) continue;
    const int density = std::max(int(grid.density(v)) - decrement, 0);
    if (density > 0) {
      voxels_->setDensity(v, Density(density));
      ++total.samplesDecremented;
      continue;
    }
    total.removedFill += grid.fill(v);
    ++total.samplesRemoved;
    ++total.voxelsEmptied;
    voxels_->removeVoxel(v);
  }
  return total;
}

}  // namespace osteon::simulation
