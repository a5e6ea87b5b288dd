// The built-in humerus as the simulation tests drill it: a Session on its mesh with a portal-5
// path, or the same bone as parts (grid, hierarchy, drilling simulation) for tests of the
// parts themselves.
#pragma once

#include <memory>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/session.h"

namespace osteon::test {

// A session on the built-in humerus (geometry::defaultHumerusModel()) with these options.
simulation::Session humerusSession(const simulation::SessionOptions& options = {});

// The built-in humerus voxelized at 1.2 mm as a bone from a grid (no mesh behind it: refined
// voxels split their fill evenly), with these options.
simulation::Session humerusGridSession(const simulation::SessionOptions& options = {});
// The portal-5 plan on the built-in humerus's mesh (its head fitted to the mesh, whatever the
// session's bone), for the session's tool, `durationS` seconds long.
simulation::PortalPlan humerusMeshPortalPlan(const simulation::Session& session, double durationS);

// The session's portal-5 (five o'clock) path, `durationS` seconds long, in bone from its first
// second.
simulation::DrillPath portalFivePath(const simulation::Session& session, double durationS);

// The built-in humerus at 1.2 mm, static (no refinement), with the default drill, and its
// portal-5 plan of `pathS` seconds.
struct HumerusParts {
  const geometry::HumerusModel& model = geometry::defaultHumerusModel();
  geometry::VoxelGrid grid;
  geometry::DynamicProximityHierarchy hierarchy;
  std::unique_ptr<simulation::DrillingSimulation> sim;
  simulation::PortalPlan plan;
  explicit HumerusParts(double pathS);
};

}  // namespace osteon::test
