#include "osteon/validation/validate.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "osteon/core/error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/experiment.h"
#include "osteon/simulation/session.h"
#include "osteon/validation/shard.h"

namespace osteon::validation {

namespace sim = osteon::simulation;

namespace {

// The guarantees a surface must keep, in words when broken.
void surfaceFailures(const MeshReport& r, const CrackMetric& c, const char* when,
                     std::vector<std::string>& out) {
  const auto add = [&](bool broken, const std::string& what) {
    if (broken) out.push_back(std::string(when) + ": " + what);
  };
  add(r.topology.borderEdges > 0, std::to_string(r.topology.borderEdges) + " border edges");
  add(r.topology.nonManifoldEdges + r.topology.nonManifoldVertices > 0,
      std::to_string(r.topology.nonManifoldEdges + r.topology.nonManifoldVertices) +
          " non-manifold elements");
  add(r.selfIntersections > 0, std::to_string(r.selfIntersections) +
                                   (r.selfIntersectionsCapped ? "+" : "") +
                                   " self-intersecting pairs");
  add(c.red > 0, std::to_string(c.red) + " red pixels");
}

// Both portals drilled on a fresh session (static or dynamic by levels), each path's
// collisions cross-checked, then the drilled surface checked: failures go into c.
void drillCase(const std::shared_ptr<const sim::BoneModel>& bone, int levels,
               const geometry::SurfaceOptions& so, const ValidationOptions& options,
               const CrackMetricOptions& crackOptions, ValidationCase& c) {
  sim::SessionOptions drilling;
  drilling.levels = levels;
  sim::Session session(bone, drilling);
  const sim::DrillingSimulation& simulation = session.simulation();
  for (const sim::Portal portal : {sim::Portal::FiveOClock, sim::Portal::SevenOClock}) {
    const sim::PortalPlan plan = session.portalPath(portal);
    PortalRun run;
    run.portal = sim::portalName(portal);
    CollisionCheckOptions check;
    check.everySteps = options.checkEverySteps;
    check.method = so.method;  // naive: its surface re-extracted whole at each check
    run.collisions = crossCheckCollisions(session, plan.path, check);
    const sim::RunSummary& s = run.collisions.run.summary;
    run.maxForceN = s.maxForceN;
    run.jitterN = s.jitterN;
    run.nonFiniteForces = s.totals.nonFiniteForces;
    if (run.collisions.misses > 0) {
      c.failures.push_back(run.portal + ": " + std::to_string(run.collisions.misses) +
                           " collision misses");
    }
    if (run.nonFiniteForces > 0) c.failures.push_back(run.portal + ": NaN or infinite force");
    if (run.maxForceN > simulation.tool().maxForceN + 1e-9)
      c.failures.push_back(run.portal + ": force above the cap");
    c.portals.push_back(std::move(run));
    // The next path starts its own clock; after the last, the refined voxels stay
    // so the drilled surface below includes them.
    if (portal == sim::Portal::FiveOClock) session.simulation().voxels().expireAll();
  }
  const geometry::TriangleMesh drilled =
      so.method == geometry::SurfaceMethod::CrackFree
          ? geometry::extractSurface(session.grid(), simulation.voxels(), so).toTriangleMesh()
          : geometry::extractSurface(session.grid(), so).toTriangleMesh();
  c.after = checkMesh(drilled);
  c.afterCracks = measureCracks(drilled, crackOptions);
  surfaceFailures(c.after, c.afterCracks, "after drilling", c.failures);
}

}  // namespace

std::vector<double> ValidationModel::voxelSizesMm(const std::vector<double>& requested) const {
  return volume ? std::vector<double>{volume->voxelSizeMm()} : requested;
}

bool ValidationReport::pass() const {
  for (const ValidationCase& c : cases) {
    if (c.method == geometry::SurfaceMethod::CrackFree && !c.pass()) return false;
  }
  return true;
}

ValidationReport runValidation(const std::vector<ValidationModel>& models,
                               const ValidationOptions& options,
                               const std::function<void(const ValidationCase&)>& progress) {
  ValidationReport report;
  CrackMetricOptions crackOptions;
  crackOptions.pixels = options.crackPixels;
  const std::vector<CaseGroup> groups = caseGroups(models, options);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (options.groups && !std::binary_search(options.groups->begin(), options.groups->end(), g))
      continue;
    const ValidationModel& model = models[groups[g].model];
    const double voxelMm = groups[g].voxelSizeMm;
    const Clock::time_point setupStart = Clock::now();
    const std::shared_ptr<const sim::BoneModel> bone =
        model.volume
            ? sim::BoneModel::fromGrid(*model.volume, model.name)
            : sim::BoneModel::fromMesh(model.mesh, voxelMm, model.name, model.loadScaleToMm);
    // Drilling needs a humeral head; a bone without one is checked but not drilled.
    bool head = false;
    if (options.drill) {
      try {
        bone->humeralHead();
        head = true;
      } catch (const InputError&) {
      }
    }
    const geometry::VoxelGrid& original = bone->grid();
    const double setupMs = msSince(setupStart);
    for (const geometry::SurfaceMethod method :
         {geometry::SurfaceMethod::CrackFree, geometry::SurfaceMethod::Naive}) {
      geometry::SurfaceOptions so;
      so.method = method;
      const Clock::time_point start = Clock::now();
      geometry::SurfaceTimings timings;
      const geometry::TriangleMesh surface =
          geometry::extractSurface(original, so, &timings).toTriangleMesh();
      const double extractMs = msSince(start);
      ValidationCase base;
      base.timings = timings;
      base.voxels = original.countVoxels(geometry::kFillHalf);
      base.model = model.name;
      base.voxelSizeMm = voxelMm;
      base.method = method;
      base.extractMs = extractMs;
      base.triangles = surface.triangleCount();
      base.vertices = surface.vertexCount();
      base.before = checkMesh(surface);
      base.cracks = measureCracks(surface, crackOptions);
      try {
        base.accuracyKnown = !model.volume;  // a volume has no source polygons
        if (base.accuracyKnown) base.accuracy = compareMeshes(surface, model.mesh);
      } catch (const std::invalid_argument&) {
        base.accuracyKnown = false;  // the source is not a polygon mesh
      }
      surfaceFailures(base.before, base.cracks, "before drilling", base.failures);
      base.setupMs = setupMs;
      base.surfaceMs = msSince(start);
      for (const int levels : {0, 2}) {
        ValidationCase c = base;
        const Clock::time_point drillStart = Clock::now();
        c.mode = levels == 0 ? ForceMode::Static : ForceMode::Dynamic;
        if (head) drillCase(bone, levels, so, options, crackOptions, c);
        c.drillMs = msSince(drillStart);
        if (progress) progress(c);
        report.cases.push_back(std::move(c));
      }
    }
  }
  return report;
}

}  // namespace osteon::validation
