// The collision-miss cross-check (design.md "Metrics"): along a drill path, the voxel model's
// contact (bone samples between the tool's layers, which give the force) against the surface
// the trainee sees (the incrementally updated crack-free surface): does the tool's outer
// sphere reach it? A miss is a force with no visible contact; a false contact is visible
// contact with no force. Both within a tolerance in base voxel sizes, since the surface
// stands for the voxels to within about half a voxel.
#pragma once

#include "osteon/geometry/surface.h"
#include "osteon/simulation/runner.h"

#include <cstdint>

namespace osteon::validation {

struct CollisionCheckOptions {
  int everySteps = 10;          // surface queried every N haptic steps (each needs a BVH)
  double toleranceVoxels = 1.0;
  bool updateSurface = true;    // false: the surface stays as it was before drilling (a visual
                                // thread that fell behind; the check must then see misses)
  // The surface the trainee would see: the incremental crack-free one, or the seed's naive
  // marching cubes extracted whole from the grid at each check.
  geometry::SurfaceMethod method = geometry::SurfaceMethod::CrackFree;
};

struct CollisionCheckResult {
  std::uint64_t steps = 0;
  std::uint64_t checked = 0;
  std::uint64_t contacts = 0;        // checked steps where the voxels say contact
  std::uint64_t misses = 0;          // voxels: contact; surface: farther than r_o + tolerance
  std::uint64_t falseContacts = 0;   // voxels: none; surface: nearer than r_o - tolerance
  double worstMissMm = 0.0;          // surface distance beyond r_o at the worst miss
  simulation::RunResult run;         // the run itself (force log and summary)
};

// Runs the path in the deterministic mode (as simulation::runDeterministic, surface updated
// every step) and checks the tool's cutting part against the surface as it goes.
CollisionCheckResult crossCheckCollisions(simulation::DrillingSimulation& sim, geometry::VoxelGrid& grid,
                                          const simulation::DrillPath& path,
                                          const CollisionCheckOptions& options = {});

}  // namespace osteon::validation
