#include "support/carve.h"

#include <algorithm>
#include <vector>

#include <glm/geometric.hpp>

namespace osteon::test {

bool Cut::contains(const glm::dvec3& pMm) const {
  const glm::dvec3 ab = bMm - aMm;
  const double len2 = glm::dot(ab, ab);
  double t = len2 > 0.0 ? glm::dot(pMm - aMm, ab) / len2 : 0.0;
  if (sideOnly && (t < 0.0 || t > 1.0)) return false;
  t = std::clamp(t, 0.0, 1.0);
  const glm::dvec3 d = pMm - (aMm + t * ab);
  return glm::dot(d, d) <= radiusMm * radiusMm;
}

Carved carve(geometry::RefinedVoxels& voxels, const Cut& cut, int decrement) {
  Carved out;
  const geometry::VoxelGrid& grid = voxels.grid();
  // Every voxel with bone whose cube may meet the cut: within its bounding sphere and a voxel
  // diagonal of the centre.
  const glm::dvec3 mid = 0.5 * (cut.aMm + cut.bMm);
  const double reach =
      0.5 * glm::length(cut.bMm - cut.aMm) + cut.radiusMm + 2.0 * grid.voxelSizeMm();
  const glm::ivec3 lo =
      glm::max(glm::ivec3(glm::floor(grid.gridFromWorld(mid - reach))), glm::ivec3(0));
  const glm::ivec3 hi =
      glm::min(glm::ivec3(glm::ceil(grid.gridFromWorld(mid + reach))), grid.dims() - 1);
  std::vector<glm::ivec3> bone;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x)
        if (grid.fill({x, y, z}) > 0) bone.push_back({x, y, z});
  geometry::RefinedVoxels::SampleBlock block;
  for (const glm::ivec3& v : bone) {
    if (voxels.openBlock(v, block)) {
      const int n = block.perEdge;
      std::uint64_t removed = 0, removedFill = 0;
      for (int i = 0; i < n * n * n; ++i) {
        const glm::dvec3 c =
            block.cornerMm + (glm::dvec3(i % n, (i / n) % n, i / (n * n)) + 0.5) * block.sampleMm;
        if (block.fill[i] == 0 || !cut.contains(c)) continue;
        block.density[i] = geometry::Density(std::max(int(block.density[i]) - decrement, 0));
        if (block.density[i] > 0) {
          ++out.samplesDecremented;
          continue;
        }
        removedFill += block.fill[i];
        block.fill[i] = 0;
        *block.occupied &= ~(std::uint64_t(1) << i);
        removed |= std::uint64_t(1) << i;
        ++out.samplesRemoved;
      }
      out.removedFill += removedFill;
      if (voxels.settleBlock(block, removed, removedFill)) ++out.voxelsEmptied;
      continue;
    }
    if (!cut.contains(grid.voxelCentreMm(v))) continue;
    const int density = std::max(int(grid.density(v)) - decrement, 0);
    if (density > 0) {
      voxels.setDensity(v, geometry::Density(density));
      ++out.samplesDecremented;
      continue;
    }
    out.removedFill += grid.fill(v);
    ++out.samplesRemoved;
    ++out.voxelsEmptied;
    voxels.removeVoxel(v);
  }
  return out;
}

}  // namespace osteon::test
