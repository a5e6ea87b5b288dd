// The seed's section 4 experiment: static against dynamic voxels on both portals, at 1.2 mm
// (1 and 2 levels), 0.9 mm and 0.72 mm (1 level), each a 7 s drilling path logged at 1 kHz in
// the deterministic mode.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/runner.h"

namespace osteon::simulation {

struct ExperimentRun {
  double voxelSizeMm = 0.0;
  Portal portal = Portal::FiveOClock;
  int levels = 0;
  RunResult result;
  std::string name() const;  // e.g. "1.2mm_portal-5_L2"
};

struct ExperimentCase {
  double voxelSizeMm;
  std::vector<int> dynamicLevels;  // compared with levels 0 (static)
};

// The seed's cases: 1.2 mm with 1 and 2 levels, 0.9 mm and 0.72 mm with 1 level.
std::vector<ExperimentCase> seedExperimentCases();

// Runs every case on both portals, static first. `progress` (may be empty) hears each run as it
// finishes. `voxelizing` gives the voxelization's options but the voxel size (the mesh's name
// and load scale for messages, the density rule); `up` the head's end (BoneSource::up). Throws
// InputError when the mesh has no humeral head to drill, or no voxel inside it at a case's voxel
// size.
std::vector<ExperimentRun> runSeedExperiment(
    const geometry::TriangleMesh& mesh, const std::vector<ExperimentCase>& cases,
    const std::function<void(const ExperimentRun&)>& progress = {},
    const geometry::VoxelizeOptions& voxelizing = {}, const std::optional<glm::dvec3>& up = {});

const char* portalName(Portal portal);

}  // namespace osteon::simulation
