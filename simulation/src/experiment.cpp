#include "osteon/simulation/experiment.h"

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"

#include <cstdio>
#include <memory>

namespace osteon::simulation {

const char* portalName(Portal portal) { return portal == Portal::FiveOClock ? "portal-5" : "portal-7"; }

std::string ExperimentRun::name() const {
  char text[64];
  std::snprintf(text, sizeof text, "%gmm_%s_L%d", voxelSizeMm, portalName(portal), levels);
  return text;
}

std::vector<ExperimentCase> seedExperimentCases() {
  return {{1.2, {1, 2}}, {0.9, {1}}, {0.72, {1}}};
}

std::vector<ExperimentRun> runSeedExperiment(const geometry::TriangleMesh& mesh,
                                             const std::vector<ExperimentCase>& cases,
                                             const std::function<void(const ExperimentRun&)>& progress,
                                             const geometry::VoxelizeOptions& voxelizing) {
  const HumeralHead head = fitHumeralHead(mesh);
  const geometry::EmbreeScene scene(mesh);
  std::vector<ExperimentRun> runs;
  for (const ExperimentCase& c : cases) {
    geometry::VoxelizeOptions vo = voxelizing;
    vo.voxelSizeMm = c.voxelSizeMm;
    vo.voxelSizeGiven = false;
    vo.requireInside = true;
    const geometry::VoxelGrid original = geometry::voxelize(mesh, vo);
    // Sampled once per voxel size: every dynamic run refines from the same fine fills.
    const geometry::FineFillSource source = geometry::FineFillSource::sample(original, mesh, scene);
    std::vector<int> levels = {0};
    levels.insert(levels.end(), c.dynamicLevels.begin(), c.dynamicLevels.end());
    for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
      for (const int l : levels) {
        geometry::VoxelGrid grid = original;  // every run drills fresh bone
        auto hierarchy = geometry::DynamicProximityHierarchy::build(grid, geometry::DphBuildOptions{});
        DrillingOptions options;
        options.levels = l;
        DrillingSimulation sim(grid, hierarchy, l > 0 ? &source : nullptr, ToolKind::Drill, ToolOptions{}, options);
        const PortalPlan plan = makePortalPath(portal, head, mesh, sim.tool().parts[0].outerRadiusMm);
        ExperimentRun run;
        run.voxelSizeMm = c.voxelSizeMm;
        run.portal = portal;
        run.levels = l;
        run.result = runDeterministic(sim, grid, plan.path, nullptr);
        if (progress) progress(run);
        runs.push_back(std::move(run));
      }
    }
  }
  return runs;
}

}  // namespace osteon::simulation
