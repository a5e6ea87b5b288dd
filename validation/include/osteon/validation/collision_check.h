// The collision-miss cross-check (docs/validation.md, "Collision-miss cross-check"): along a
// drill path, the voxel model's contact (bone samples between the tool's layers, which give
// the force) against the surface the trainee sees: would a collision against that mesh find
// the same bone?
//
// A miss is bone in the shell that the surface does not shield: an Embree ray from the tool's
// body to the sample's centre that meets no triangle, where a mesh-based collision would let
// the tool through (a hole in the surface, or a surface that no longer follows the bone). The
// ray runs from outside to inside the crack-free surface, both known from the voxels alone:
// it starts in a marching-cubes cell whose eight voxels are all below half full (the tool's
// centre, or the nearest such cell centre within its outer sphere) and ends at a level-0 sample
// at or above half full, or a finer sample in a cell whose eight voxels all are. The
// crack-free surface separates those two sides (closed, and every vertex stays on its own grid
// edge through smoothing), so it is crossed on the way: its misses are exactly 0, with no
// tolerance, in static and dynamic mode. Samples in cells the surface passes through
// (partial voxels, sub-voxels finer than the level-0 surface) are where the surface stands for
// the voxels only to within a cell; they are counted, not judged.
//
// A false contact is the reverse: no bone in the shell, but the surface nearer to the core
// than r_o - tolerance (Embree point query).
#pragma once

#include <cstdint>

#include "osteon/geometry/surface/surface.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/session.h"

namespace osteon::validation {

struct CollisionCheckOptions {
  int everySteps = 10;           // surface checked every N haptic steps (each needs a BVH)
  double toleranceVoxels = 1.0;  // false contacts: base voxel sizes the surface may come inside r_o
  int raysPerStep = 64;          // contact samples ray-tested per check, spread evenly (0: all)
  bool updateSurface = true;     // false: the surface stays as it was before drilling (a visual
                                 // thread that fell behind; the check must then see misses)
  // The surface the trainee would see: the incremental crack-free one, or the seed's naive
  // marching cubes extracted whole from the grid at each check.
  geometry::SurfaceMethod method = geometry::SurfaceMethod::CrackFree;
};

struct CollisionCheckResult {
  std::uint64_t steps = 0;
  std::uint64_t checked = 0;
  std::uint64_t contacts = 0;         // checked steps with bone in the cutting part's shell
  std::uint64_t misses = 0;           // contact steps with at least one missed sample
  std::uint64_t falseContacts = 0;    // no bone in the shell; surface nearer than r_o - tolerance
  std::uint64_t contactSamples = 0;   // shell samples over the checked steps
  std::uint64_t boundarySamples = 0;  // of those, not enclosed by the voxels alone: not judged
  std::uint64_t skippedSamples = 0;   // enclosed ones with no ray start known to be outside bone
  std::uint64_t skippedSteps = 0;     // contact steps with no ray to cast
  std::uint64_t raysCast = 0;         // up to raysPerStep a check, over the rest
  std::uint64_t missedSamples = 0;    // rays that met no surface
  double worstMissMm = 0.0;   // largest distance from a missed sample's centre to the surface
  simulation::RunResult run;  // the run itself (force log and summary)
};

// Runs the path in the deterministic mode (Session::run, the surface extracted afresh from the
// grid as it is at the start, then updated every step) and checks the tool's cutting part
// against the surface as it goes. The session must keep its surface (keepSurface).
CollisionCheckResult crossCheckCollisions(simulation::Session& session,
                                          const simulation::DrillPath& path,
                                          const CollisionCheckOptions& options = {});

}  // namespace osteon::validation
