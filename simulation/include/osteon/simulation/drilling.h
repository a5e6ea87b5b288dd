// One drilling step (seed 3.5): refine near the tool, compute the contact force, wear the bone
// inside the cutting layer down by one density unit, remove what reaches zero, expire refined
// voxels the tool has left. The collision thread runs this at 1 kHz; the deterministic mode
// calls it with a fixed 1 ms step.
//
// --levels 0 computes at the base voxel size (static); 1 and 2 refine near the tool and
// compute at VS/2 or VS/4 (dynamic).
#pragma once

#include <cstdint>
#include <memory>

#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/simulation/contact.h"
#include "osteon/simulation/cutting.h"
#include "osteon/simulation/removal.h"
#include "osteon/simulation/tool.h"

namespace osteon::simulation {

struct DrillingOptions {
  int levels = 2;                          // 0 static, 1 or 2 dynamic
  int decrement = 1;                       // density units per drilling step (seed: d - 1)
  geometry::RefinementOptions refinement;  // depth is taken from `levels`
  // Bricks kept ready for removal in uniform bricks (2 KiB each), so a step never allocates.
  std::size_t spareBricks = 1024;
  // Hierarchy queries answered from the previous walk while the tool moves less than this
  // many base voxels (geometry::DphNearCache); 0: walk at every query. The same forces and
  // removal either way.
  double querySkinVoxels = 1.0;
  // Hierarchy nodes per step spent gathering a query's next answer before the tool leaves the
  // skin (0: walk at once when it does), so that no step pays a whole walk from cold memory.
  std::size_t querySliceNodes = 256;
  // Refine wherever bone touches a part: every part's shell (the drill's shaft too) gets the
  // finest level over the bone it reaches. false: only around the cutting parts, as the seed
  // describes (a tilted shaft then pushes with base voxels). The seed's scripted runs give the
  // same force logs either way: their shaft follows the tip through its hole.
  bool refineShells = true;
  // Voxels newly refined per step for the shells at most (0: no limit), so that a pose
  // meeting much new bone at once does not overrun the step; the rest are refined in the
  // following steps, the force using their coarser samples (the same bone volume) meanwhile.
  // The cutting parts' refinement is never deferred: a cut acts on the finest samples.
  std::size_t refineBudgetVoxels = 48;
  // The shells' refinement reaches this many base voxels further and walks again only once a
  // part has moved that far (or half the refinement timeout has passed, or voxels were left
  // for later): the voxels a shell can reach meanwhile are already refined. 0: every step.
  double shellRefineSkinVoxels = 0.25;
  // Seed: every part's shell pushes by eq. (2). Calibrated (cutting.h): the cutting parts push
  // through the proxy's feed law instead; the others (the shaft) still by eq. (2).
  ForceModelKind forceModel = ForceModelKind::Seed;
};

// Throws InputError naming the value for levels outside 0..2 or a decrement below 1.
void validateDrillingOptions(const DrillingOptions& options);

struct StepInput {
  // A constructor, not an aggregate: {t, pose, on} keeps the default settings.
  StepInput(double t = 0.0, const ToolPose& p = {}, bool on = false, const DrillSettings& s = {})
      : tS(t), pose(p), drillOn(on), settings(s) {}
  double tS;
  ToolPose pose;
  bool drillOn;
  DrillSettings settings;  // rpm and irrigation (the calibrated model and heat read them)
};

struct StepOutput {
  ContactForce contact;  // from the bone before this step's removal
  RemovalResult removal;
  int refined = 0;   // voxels newly refined this step
  int deferred = 0;  // voxels a shell reached but left for later steps (the budget)
};

struct DrillingTotals {
  std::uint64_t steps = 0;
  std::uint64_t removedFill = 0;  // grid fill units: exact volume
  std::uint64_t samplesRemoved = 0;
  std::uint64_t voxelsEmptied = 0;
  std::uint64_t nonFiniteForces = 0;
  std::uint64_t brickAllocations = 0;  // bricks a step had to allocate (the spare pool ran out)
  std::uint64_t cutOverflows = 0;      // cuts that found more voxels than reserved (the rest left)
  std::uint64_t refinePoolExhausted = 0;  // voxels left coarse because the refinement pool was full
  std::uint64_t maskOverflows = 0;        // removal masks the table had no room for
  // Hierarchy queries (contact shells and cuts): walked, or answered from their caches.
  std::uint64_t queryWalks = 0, queryReuses = 0;
  std::uint64_t stepsThatWalked = 0;
  // Shell refinement spread over later steps by the budget: steps that left voxels coarse,
  // and those voxels summed over the steps (a voxel left for 3 steps counts 3).
  std::uint64_t stepsDeferred = 0, voxelsDeferred = 0;
};

class DrillingSimulation {
 public:
  // grid, hierarchy (and source, which may be null) must outlive this object.
  DrillingSimulation(geometry::VoxelGrid& grid, geometry::DynamicProximityHierarchy& hierarchy,
                     const geometry::FineFillSource* source, const ToolKind kind,
                     const ToolOptions& toolOptions, const DrillingOptions& options);

  // No allocation, no lock, no throw.
  StepOutput step(const StepInput& input);

  const Tool& tool() const { return model_.tool(); }
  const ForceModel& forceModel() const { return model_; }
  double finestVoxelMm() const { return finestVoxelMm_; }
  int levels() const { return levels_; }
  const DrillingTotals& totals() const { return totals_; }
  double removedVolumeMm3() const;
  geometry::RefinedVoxels& voxels() { return *voxels_; }
  const geometry::RefinedVoxels& voxels() const { return *voxels_; }
  const geometry::VoxelGrid& grid() const { return *grid_; }
  // The grid it drills, for a runtime that hands its changed bricks on (live.h).
  geometry::VoxelGrid& grid() { return *grid_; }

 private:
  geometry::VoxelGrid* grid_;
  int levels_;
  int decrement_;
  double finestVoxelMm_;
  std::unique_ptr<geometry::RefinedVoxels> voxels_;
  MaterialRemoval removal_;
  ForceModel model_;
  ContactCaches contactCaches_;
  std::array<geometry::DphNearCache, kMaxToolParts> cutCaches_;
  std::array<geometry::DphNearCache, kMaxToolParts> refineCaches_;
  std::array<geometry::DphNearCache, kMaxToolParts> shellRefineCaches_;
  bool refineShells_ = true;
  std::size_t refineBudget_ = 0;
  double shellSkinMm_ = 0.0;
  double shellWalkEveryS_ = 1.0;
  // Per part: where its core was at its shell refinement's last walk, when, and whether that
  // walk left voxels for later.
  struct ShellWalk {
    glm::dvec3 aMm{0.0}, bMm{0.0};
    double tS = 0.0;
    bool walked = false, deferred = false;
  };
  std::array<ShellWalk, kMaxToolParts> shellWalks_{};
  bool cached_ = false;
  DrillingTotals totals_;
  std::uint64_t spareMissesAtStart_ = 0;
};

}  // namespace osteon::simulation
