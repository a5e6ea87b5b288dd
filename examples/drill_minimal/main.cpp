// Embedding osteon: drill the 5 o'clock portal of the built-in humerus for one second in the
// deterministic mode (1 kHz) and print the peak force and the bone removed.
#include <cstdio>
#include <exception>

#include "osteon/core/error.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/session.h"

int main() {
  using namespace osteon::simulation;
  try {
    // What to open: `default` is the built-in right proximal humerus, already in millimetres
    // (a mesh file takes its units, e.g. source.units = "m"; a volume has its own voxel size).
    BoneSource source;
    source.input = "default";
    source.voxelSizeMm = 1.2;  // base voxels
    const OpenedBone bone = BoneModel::open(source);

    SessionOptions options;
    options.levels = 2;  // refined to 0.6 and 0.3 mm near the tool
    options.tool = ToolKind::Drill;
    Session session(bone.bone, options);

    PortalPathOptions pathOptions;
    pathOptions.durationS = 1.0;
    const PortalPlan plan = session.portalPath(Portal::FiveOClock, pathOptions);

    const RunResult result = session.run(plan.path);  // the same input, the same log
    std::printf("steps: %zu\n", result.log.size());
    std::printf("peak force: %.3f N\n", result.summary.maxForceN);
    std::printf("removed volume: %.3f mm^3\n", result.summary.removedVolumeMm3);
    return 0;
  } catch (const osteon::InputError& e) {
    std::fprintf(stderr, "drill_minimal: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "drill_minimal: internal error: %s\n", e.what());
    return 3;
  }
}
