#include "osteon/validation/collision_check.h"

#include "osteon/geometry/embree_scene.h"

#include <algorithm>
#include <cmath>

namespace osteon::validation {

CollisionCheckResult crossCheckCollisions(simulation::DrillingSimulation& sim, geometry::VoxelGrid& grid,
                                          const simulation::DrillPath& path, const CollisionCheckOptions& options) {
  CollisionCheckResult result;
  geometry::SurfaceUpdater surface(grid, geometry::SurfaceOptions{});
  const simulation::ToolPart& tip = sim.tool().parts[0];  // the cutting part
  const double tolerance = options.toleranceVoxels * grid.voxelSizeMm();
  simulation::DeterministicOptions run;
  run.afterStep = [&](std::size_t step, const simulation::StepInput& in, const simulation::StepOutput& out) {
    if (options.everySteps <= 0 || step % std::size_t(options.everySteps) != 0) return;
    const bool voxelContact = out.contact.samples > 0;
    geometry::SurfaceOptions naive;
    naive.method = geometry::SurfaceMethod::Naive;
    const geometry::TriangleMesh mesh = options.method == geometry::SurfaceMethod::Naive
                                            ? geometry::extractSurface(grid, naive).toTriangleMesh()
                                            : surface.mesh().toTriangleMesh();
    if (mesh.triangles.empty()) return;
    const geometry::EmbreeScene scene(mesh);
    // The distance from the cutting part's core to the surface: its centre for a sphere, the
    // nearest of points along the core for a cylinder.
    const glm::dvec3 a = in.pose.toWorld(tip.aMm), b = in.pose.toWorld(tip.bMm);
    const int samples = std::max(1, int(std::ceil(glm::length(b - a) / (0.25 * tip.outerRadiusMm)))) + 1;
    const double reach = tip.outerRadiusMm + 2.0 * tolerance;
    double distance = -1.0;
    for (int k = 0; k < samples; ++k) {
      const glm::dvec3 p = samples == 1 ? a : a + (b - a) * (double(k) / double(samples - 1));
      const double d = scene.distanceWithin(p, reach);
      if (d >= 0.0 && (distance < 0.0 || d < distance)) distance = d;
    }
    ++result.checked;
    if (voxelContact) ++result.contacts;
    if (voxelContact && (distance < 0.0 || distance > tip.outerRadiusMm + tolerance)) {
      ++result.misses;
      result.worstMissMm = std::max(result.worstMissMm, (distance < 0.0 ? reach : distance) - tip.outerRadiusMm);
    }
    if (!voxelContact && distance >= 0.0 && distance < tip.outerRadiusMm - tolerance) ++result.falseContacts;
  };
  if (!options.updateSurface) run.remeshEverySteps = 0;
  result.run = simulation::runDeterministic(sim, grid, path, &surface, run);
  result.steps = result.run.summary.steps;
  return result;
}

}  // namespace osteon::validation
