// Material removal (seed 3.5): every bone sample whose centre lies in a tool's cutting volume
// loses density each drilling step, and a sample worn to d <= 0 is removed, its fill leaving
// the grid (and a level-0 voxel left empty leaving the hierarchy). Works at the finest level
// present through the refined voxels' sample-mutation interface (refinement.h).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>

#include "osteon/geometry/hierarchy/refinement.h"

namespace osteon::simulation {

// A tool's cutting volume: the points within radiusMm of the segment a-b, a sphere when
// a == b. sideOnly keeps only points whose projection falls on the segment: a cylinder
// without end caps, for a shaver that cuts with its side.
struct CutVolume {
  glm::dvec3 aMm{0.0};
  glm::dvec3 bMm{0.0};
  double radiusMm = 0.0;
  bool sideOnly = false;

  static CutVolume sphere(const glm::dvec3& centreMm, double radiusMm) {
    return CutVolume{centreMm, centreMm, radiusMm, false};
  }
  glm::dvec3 centreMm() const { return 0.5 * (aMm + bMm); }
  double boundingRadiusMm() const { return 0.5 * glm::length(bMm - aMm) + radiusMm; }
  bool contains(const glm::dvec3& pMm) const {
    const glm::dvec3 ab = bMm - aMm;
    const double len2 = glm::dot(ab, ab);
    double t = len2 > 0.0 ? glm::dot(pMm - aMm, ab) / len2 : 0.0;
    if (sideOnly && (t < 0.0 || t > 1.0)) return false;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    const glm::dvec3 d = pMm - (aMm + t * ab);
    return glm::dot(d, d) <= radiusMm * radiusMm;
  }
};

struct RemovalResult {
  std::uint64_t removedFill = 0;  // fill units taken out of the grid (exact volume)
  std::uint32_t samplesRemoved = 0;
  std::uint32_t samplesDecremented = 0;
  std::uint32_t voxelsEmptied = 0;  // level-0 voxels that left grid and hierarchy
  double removedVolumeMm3(double voxelVolumeMm3) const {
    return double(removedFill) / double(geometry::kFillFull) * voxelVolumeMm3;
  }
};

class MaterialRemoval {
 public:
  // `voxels` must outlive this object. Reserves room for the voxels of a cut (allocates).
  explicit MaterialRemoval(geometry::RefinedVoxels& voxels, std::size_t cutVoxels = 4096);

  // Room for a cut's voxels (its reach's): reserve the most a cut can reach before the loop
  // starts (allocates). A cut that still finds more is counted in cutOverflows() and leaves
  // the rest for the next step.
  void reserveCutVoxels(std::size_t voxels) {
    if (voxels > found_.capacity()) found_.reserve(voxels);
  }
  std::uint64_t cutOverflows() const { return cutOverflows_; }

  // Every sample in the volume loses `decrement` density; one at d <= 0 is removed. No
  // allocation, lock or throw. `cache` (may be null): the hierarchy query's cache for this
  // call site (dph.h); the same removal with or without it.
  RemovalResult removeIn(const CutVolume& volume, int decrement = 1,
                         geometry::DphNearCache* cache = nullptr);
  RemovalResult removeInSphere(const glm::dvec3& centreMm, double radiusMm, int decrement = 1) {
    return removeIn(CutVolume::sphere(centreMm, radiusMm), decrement);
  }

 private:
  RemovalResult removeFromBlock(const geometry::RefinedVoxels::SampleBlock& block,
                                const CutVolume& volume, int decrement);

  geometry::RefinedVoxels* voxels_;
  std::vector<glm::ivec3> found_;  // voxels of the current cut (reserved)
  std::uint64_t cutOverflows_ = 0;
};

}  // namespace osteon::simulation
