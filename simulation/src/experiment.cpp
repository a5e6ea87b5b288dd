#include "osteon/simulation/experiment.h"

#include <cstdio>
#include <memory>

#include "osteon/simulation/session.h"

namespace osteon::simulation {

const char* portalName(Portal portal) {
  return portal == Portal::FiveOClock ? "portal-5" : "portal-7";
}

std::string ExperimentRun::name() const {
  char text[64];
  std::snprintf(text, sizeof text, "%gmm_%s_L%d", voxelSizeMm, portalName(portal), levels);
  return text;
}

std::vector<ExperimentCase> seedExperimentCases() {
  return {{1.2, {1, 2}}, {0.9, {1}}, {0.72, {1}}};
}

std::vector<ExperimentRun> runSeedExperiment(
    const geometry::TriangleMesh& mesh, const std::vector<ExperimentCase>& cases,
    const std::function<void(const ExperimentRun&)>& progress,
    const geometry::VoxelizeOptions& voxelizing, const std::optional<glm::dvec3>& up) {
  std::vector<ExperimentRun> runs;
  for (const ExperimentCase& c : cases) {
    // One bone per voxel size, its fine fills sampled once: every run drills a fresh copy.
    geometry::VoxelizeOptions vo = voxelizing;
    vo.voxelSizeGiven = false;
    const std::shared_ptr<const BoneModel> bone = BoneModel::fromMesh(
        mesh, c.voxelSizeMm, voxelizing.meshName.empty() ? "mesh" : voxelizing.meshName,
        voxelizing.loadScaleToMm, vo, true, up);
    std::vector<int> levels = {0};
    levels.insert(levels.end(), c.dynamicLevels.begin(), c.dynamicLevels.end());
    for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
      for (const int l : levels) {
        SessionOptions options;
        options.levels = l;
        options.keepSurface = false;  // forces only: no visual work
        Session session(bone, options);
        ExperimentRun run;
        run.voxelSizeMm = c.voxelSizeMm;
        run.portal = portal;
        run.levels = l;
        run.result = session.run(session.portalPath(portal).path);
        if (progress) progress(run);
        runs.push_back(std::move(run));
      }
    }
  }
  return runs;
}

}  // namespace osteon::simulation
