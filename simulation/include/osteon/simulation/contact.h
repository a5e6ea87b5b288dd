// Collision and the seed's force model (section 3.5, eqs. 1-2), at the finest level present
// near the tool.
//
// For each tool part, the bone samples (level-0 voxels, or level -1/-2 sub-voxels where the
// hierarchy refined) whose centres lie in the shell between the inner and outer layer push the
// tool:
//   direction (eq. 1) = normalize(sum_k w_k (P_k - C_k)), P_k the closest point of the part's
//                       core to the sample centre C_k (the tool centre for a sphere, as the
//                       seed), w_k the sample's bone in finest-voxel units
//   magnitude (eq. 2) = N_max n / c, clamped to N_max, n = sum_k w_k
//   c = the maximum count, the number of finest voxels the shell holds: shell volume / v_min^3,
//       for a sphere 4/3 pi (r_o^3 - r_i^3) / v_min^3, for a capsule or cylinder the same with
//       its own shell volume (Tool::literalSeedCount: the seed's printed (r_o^3 - r_i^3) /
//       v_min^3, which counts voxels as balls of radius v_min, 4.19 times too few, so the force
//       saturates once a quarter of the shell holds bone: a drill in its own hole is then
//       always at N_max)
// w_k = fill_k / full level-0 fill x (VS / v_min)^3: a full finest sample counts 1, as in the
// seed's voxel count; a partial or coarser one counts its bone volume, so n is the bone volume
// in the shell over v_min^3 at every level. The parts' forces add; the sum is clamped to
// N_max. A non-finite result becomes zero force and is counted.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/simulation/tool.h"

namespace osteon::simulation {

struct ContactForce {
  glm::dvec3 forceN{0.0};
  double magnitudeN = 0.0;
  double contactVoxels = 0.0;  // n, summed over parts
  std::uint32_t samples = 0;   // samples in the shells
  int level = 0;               // finest level among them (0, -1, -2)
  bool nonFinite = false;      // zero force returned in place of a NaN or Inf
};

// The hierarchy-query caches compute() may use, one per tool part's shell
// (geometry::DphNearCache): owned by whoever steps the model, so compute() stays const.
struct ContactCaches {
  std::array<geometry::DphNearCache, kMaxToolParts> shell;
};

class ForceModel {
 public:
  // finestVoxelMm: v_min; baseVoxelMm: the grid's voxel size. cuttingPartsPush false: the
  // cutting parts' bone is counted (contactVoxels) but gives no force (the calibrated model,
  // whose proxy renders their resistance: cutting.h).
  ForceModel(const Tool& tool, double finestVoxelMm, double baseVoxelMm,
             bool cuttingPartsPush = true);

  // c of eq. (2) for a part.
  double maxCount(int part) const { return maxCount_[std::size_t(part)]; }
  const Tool& tool() const { return tool_; }

  // Samples come from `voxels` at the finest level it holds near the tool (call refineAround
  // first in dynamic mode). No allocation, no lock, no throw.
  // With caches (may be null), the same force from fewer hierarchy walks while the tool
  // moves less than the caches' skin between calls.
  ContactForce compute(geometry::RefinedVoxels& voxels, const ToolPose& pose,
                       ContactCaches* caches = nullptr) const;
  // Caches for this model's parts with the given skin and slices (geometry::DphNearCache),
  // sized so that answers always fit and ready for `voxels`' hierarchy.
  ContactCaches makeCaches(double skinMm, std::size_t sliceNodes,
                           const geometry::RefinedVoxels& voxels) const;
  // The samples in part `part`'s shell, exactly those compute() counts, for checks that hold
  // the voxels' contact against something else (the surface). Allocates: not for the loop.
  std::vector<geometry::VoxelSample> shellSamples(geometry::RefinedVoxels& voxels,
                                                  const ToolPose& pose, int part) const;

 private:
  Tool tool_;
  double finestVoxelMm_;
  double weightPerFill_;  // (VS / v_min)^3 / kFillFull
  bool cuttingPartsPush_ = true;
  std::array<double, kMaxToolParts> maxCount_{};
};

}  // namespace osteon::simulation
