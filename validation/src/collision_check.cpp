#include "osteon/validation/collision_check.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <glm/common.hpp>

#include "osteon/geometry/voxels/embree_scene.h"

namespace osteon::validation {

namespace {

// Marching-cubes cells are the cubes between eight voxel centres. The one holding pointMm is
// `side`: all eight voxels at or above half full (inside), or all below (outside). Such a
// cell holds no piece of the crack-free surface, not even on its faces (a triangle reaches a
// face only through vertices on that face's edges, and an edge between two voxels on one side
// has none), so every point of it is on its corners' side of that surface.
enum class Side { Inside, Outside };
bool cellIs(const geometry::VoxelGrid& grid, const glm::dvec3& pointMm, Side side) {
  const glm::ivec3 first(glm::floor(grid.gridFromWorld(pointMm) - 0.5));
  for (int c = 0; c < 8; ++c) {
    const bool inside =
        grid.fill(first + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1)) >= geometry::kFillHalf;
    if (inside != (side == Side::Inside)) return false;
  }
  return true;
}

// Whether the crack-free surface encloses a sample, by the voxels alone: a level-0 sample
// (a corner of the marching cubes) at or above half full, a finer one in an inside cell. The
// rest lie where the surface stands for the voxels only to within a cell: boundary samples.
bool enclosed(const geometry::VoxelGrid& grid, const geometry::VoxelSample& s) {
  return s.level == 0 ? s.fill >= geometry::kFillHalf : cellIs(grid, s.centreMm, Side::Inside);
}

// Where rays to the bone around a core point start: the point itself when its cell is
// outside, else the centre of the outside cell nearest to it within the outer layer. Any start
// in the outer sphere keeps the ray to a shell sample inside that sphere (it is convex), so
// the ray is the tool reaching that bone. None when no cell there is outside: the tool is
// buried in bone the surface shows around it (the tip entering before it has cut its way).
std::optional<glm::dvec3> rayStart(const geometry::VoxelGrid& grid, const glm::dvec3& coreMm,
                                   double radiusMm) {
  if (cellIs(grid, coreMm, Side::Outside)) return coreMm;
  const glm::dvec3 g =
      grid.gridFromWorld(coreMm) - 1.0;  // cell `first` has its centre at first + 1
  const double r = radiusMm / grid.voxelSizeMm();
  const glm::ivec3 lo(glm::floor(g - r)), hi(glm::ceil(g + r));
  std::optional<glm::dvec3> best;
  double bestDistance = radiusMm;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const glm::dvec3 centre = grid.worldFromGrid(glm::dvec3(x, y, z) + 1.0);
        const double d = glm::length(centre - coreMm);
        if (d <= bestDistance && cellIs(grid, centre, Side::Outside)) {
          best = centre;
          bestDistance = d;
        }
      }
  return best;
}

glm::dvec3 nearestOnSegment(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& p) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

struct Ray {
  glm::dvec3 fromMm;
  glm::dvec3 toMm;  // a contact sample's centre
};

}  // namespace

CollisionCheckResult crossCheckCollisions(simulation::Session& session,
                                          const simulation::DrillPath& path,
                                          const CollisionCheckOptions& options) {
  CollisionCheckResult result;
  session.resetSurface();
  simulation::DrillingSimulation& sim = session.simulation();
  const geometry::VoxelGrid& grid = session.grid();
  const simulation::ToolPart& tip = sim.tool().parts[0];  // the cutting part
  const double tolerance = options.toleranceVoxels * grid.voxelSizeMm();
  std::vector<Ray> rays;
  simulation::DeterministicOptions run;
  run.afterStep = [&](std::size_t step, const simulation::StepInput& in,
                      const simulation::StepOutput&) {
    if (options.everySteps <= 0 || step % std::size_t(options.everySteps) != 0) return;
    geometry::SurfaceOptions naive;
    naive.method = geometry::SurfaceMethod::Naive;
    const geometry::TriangleMesh mesh = options.method == geometry::SurfaceMethod::Naive
                                            ? geometry::extractSurface(grid, naive).toTriangleMesh()
                                            : session.surface().toTriangleMesh();
    if (mesh.triangles.empty()) return;
    const geometry::EmbreeScene scene(mesh);
    ++result.checked;
    // The voxels' contact now (after this step's removal, the state the surface shows): the
    // bone in the cutting part's shell, as the force counts it.
    const std::vector<geometry::VoxelSample> shell =
        sim.forceModel().shellSamples(sim.voxels(), in.pose, 0);
    const glm::dvec3 a = in.pose.toWorld(tip.aMm), b = in.pose.toWorld(tip.bMm);
    if (!shell.empty()) {
      ++result.contacts;
      result.contactSamples += shell.size();
      rays.clear();
      glm::dvec3 lastCore(NAN);
      std::optional<glm::dvec3> start;
      for (const geometry::VoxelSample& s : shell) {
        if (!enclosed(grid, s)) {
          ++result.boundarySamples;
          continue;
        }
        const glm::dvec3 core = nearestOnSegment(a, b, s.centreMm);
        if (core != lastCore) start = rayStart(grid, core, tip.outerRadiusMm);  // once for a sphere
        lastCore = core;
        if (start) {
          rays.push_back({*start, s.centreMm});
        } else {
          ++result.skippedSamples;
        }
      }
      if (rays.empty()) ++result.skippedSteps;
      // Up to raysPerStep of them, spread evenly over the shell's enumeration order (which is
      // deterministic), so the cost per check is bounded and the result reproducible.
      const std::size_t n = rays.size();
      const std::size_t cast =
          options.raysPerStep > 0 ? std::min(n, std::size_t(options.raysPerStep)) : n;
      bool missed = false;
      for (std::size_t k = 0; k < cast; ++k) {
        const Ray& ray = rays[k * n / cast];
        ++result.raysCast;
        // From outside the crack-free surface to inside it: a closed surface is crossed on the
        // way, so no tolerance is needed. A ray that gets through found a hole.
        if (scene.segmentHits(ray.fromMm, ray.toMm)) continue;
        ++result.missedSamples;
        missed = true;
        const double reach = 10.0 * tip.outerRadiusMm;
        const double toSurface = scene.distanceWithin(ray.toMm, reach);
        result.worstMissMm = std::max(result.worstMissMm, toSurface < 0.0 ? reach : toSurface);
      }
      if (missed) ++result.misses;
      return;
    }
    // No bone in the shell: the surface should not come nearer to the core than the shell's
    // outer layer, less the tolerance. Its distance from points along the core: the centre
    // for a sphere, the nearest of several for a cylinder.
    const int points =
        std::max(1, int(std::ceil(glm::length(b - a) / (0.25 * tip.outerRadiusMm)))) + 1;
    const double reach = tip.outerRadiusMm - tolerance;
    if (reach <= 0.0) return;
    for (int k = 0; k < points; ++k) {
      const glm::dvec3 p = points == 1 ? a : a + (b - a) * (double(k) / double(points - 1));
      if (scene.distanceWithin(p, reach) >= 0.0) {
        ++result.falseContacts;
        break;
      }
    }
  };
  if (!options.updateSurface) run.remeshEverySteps = 0;
  result.run = session.run(path, run);
  result.steps = result.run.summary.steps;
  return result;
}

}  // namespace osteon::validation
