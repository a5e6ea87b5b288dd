#include "commands/hierarchy.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/output_file.h"
#include "support/grid_input.h"
#include "support/hierarchy_svg.h"
#include "support/output.h"

namespace osteon::cli {

namespace geo = osteon::geometry;
using nlohmann::json;

namespace {

struct HierarchyReport {
  const HierarchyOptions* options = nullptr;
  LoadedGrid loaded;
  std::optional<geo::DynamicProximityHierarchy> hierarchy;
  double buildMs = 0.0;
  std::string problem;  // the first invariant that does not hold, "" when all hold
  int sliceZ = 0;
};

// The --svg slice: the middle of the grid, or the voxel layer at --slice-z.
int sliceOf(const HierarchyOptions& options, const geo::VoxelGrid& grid) {
  if (!options.sliceZMm) return grid.dims().z / 2;
  const int sliceZ = int(std::floor(grid.gridFromWorld(glm::dvec3(0.0, 0.0, *options.sliceZMm)).z));
  if (sliceZ < 0 || sliceZ >= grid.dims().z) {
    std::ostringstream s;
    s << "--slice-z " << *options.sliceZMm << ": outside the grid (z from " << grid.originMm().z
      << " to " << grid.worldFromGrid(glm::dvec3(grid.dims())).z << " mm)";
    throw InputError(s.str());
  }
  return sliceZ;
}

json toJson(const HierarchyReport& r) {
  const HierarchyOptions& o = *r.options;
  const geo::DynamicProximityHierarchy& h = *r.hierarchy;
  const geo::VoxelGrid& grid = r.loaded.bone->grid();
  json levels = json::array();
  for (int level = 0; level < h.levelCount(); ++level) {
    levels.push_back({{"level", level},
                      {"nodes", h.nodeCount(level)},
                      {"cell_voxels", 2 * h.halfWidth(level) + 1}});
  }
  json j = {{"input", o.bone.input},
            {"voxel_size_mm", grid.voxelSizeMm()},
            {"dims", ivec3Json(grid.dims())},
            {"xi", o.xi},
            {"seed", o.seed},
            {"voxels", h.voxelCount()},
            {"levels", h.levelCount()},
            {"nodes_per_level", levels},
            {"build_ms", r.buildMs},
            {"voxelize_ms", r.loaded.voxelizeMs},
            {"memory_bytes", h.memoryBytes()},
            {"valid", r.problem.empty()},
            {"setup_ms", setupJson(r.loaded.setup)},
            {"peak_rss_mb", peakRssMb()}};
  if (!r.problem.empty()) j["problem"] = r.problem;
  if (!r.loaded.volume.is_null()) j["volume"] = r.loaded.volume;
  if (h.voxelCount() == 0) {
    j["empty"] = true;
    j["empty_reason"] = "no voxel inside";
  }
  if (!o.svg.empty()) j["svg"] = o.svg;
  return j;
}

void printText(const HierarchyReport& r) {
  const HierarchyOptions& o = *r.options;
  const geo::DynamicProximityHierarchy& h = *r.hierarchy;
  std::printf("osteon hierarchy %s: %zu voxels at %.4g mm, xi %d, seed %llu\n",
              o.bone.input.c_str(), h.voxelCount(), r.loaded.bone->grid().voxelSizeMm(), o.xi,
              static_cast<unsigned long long>(o.seed));
  for (int level = 0; level < h.levelCount(); ++level) {
    std::printf("  level %2d  %9zu nodes   cells of %lld voxels\n", level, h.nodeCount(level),
                2 * h.halfWidth(level) + 1);
  }
  std::printf("  build %.1f ms, %.2f MB; %s\n", r.buildMs, double(h.memoryBytes()) / 1e6,
              r.problem.empty() ? "all invariants hold" : r.problem.c_str());
  std::printf("%s\n", setupLine(r.loaded.setup).c_str());
  if (!r.loaded.volumeText.empty()) std::printf("%s\n", r.loaded.volumeText.c_str());
  if (!o.svg.empty()) std::printf("  wrote %s (slice z = %d)\n", o.svg.c_str(), r.sliceZ);
}

}  // namespace

int runHierarchy(const HierarchyOptions& options) {
  if (!options.svg.empty()) geo::refuseOverwritingInputs({options.svg}, options.bone.inputFiles());
  HierarchyReport r;
  r.options = &options;
  r.loaded = loadGrid(options.bone);
  const geo::VoxelGrid& grid = r.loaded.bone->grid();
  geo::DphBuildOptions build;
  build.expansionRatio = options.xi;
  build.seed = options.seed;
  const Clock::time_point start = Clock::now();
  r.hierarchy.emplace(geo::DynamicProximityHierarchy::build(grid, build));
  r.buildMs = msSince(start);
  r.loaded.setup.hierarchyMs = r.buildMs;
  r.loaded.setup.totalMs =
      msSince(r.loaded.start);  // set-up ends with the hierarchy; the checks are not part of it
  r.problem = r.hierarchy->validateAgainst(grid);
  r.sliceZ = sliceOf(options, grid);
  if (!options.svg.empty()) {
    std::ostringstream title;
    title << "DPH of " << options.bone.input << ", xi " << options.xi << ", voxel "
          << grid.voxelSizeMm() << " mm";
    writeHierarchySvg(*r.hierarchy, grid, r.sliceZ, title.str(), options.svg);
  }
  printReport(r, options.json);
  if (!r.problem.empty()) return kExitCheckFailed;
  if (r.hierarchy->voxelCount() == 0) {
    return emptyExit("hierarchy", options.bone.input, "no voxel inside", options.allowEmpty);
  }
  return kExitOk;
}

}  // namespace osteon::cli
