#include "commands/voxelize.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/session.h"
#include "support/mesh_json.h"
#include "support/output.h"

namespace osteon::cli {

namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

struct VoxelizeReport {
  const VoxelizeCommandOptions* options = nullptr;
  sim::BoneMesh loaded;
  geo::VoxelizeOptions voxelizing;
  geo::VoxelizeStats stats;
  geo::VoxelGrid grid;
  sim::SetupTimings setup;
  double writeMs = 0.0;
  double meshVolumeMm3 = 0.0, volumeMm3 = 0.0, errorPercent = 0.0;
  std::uint64_t inside = 0, touched = 0;
};

// The grid is written as NRRD whatever the name says: a name that promises a mesh or an image
// would hold NRRD bytes.
void checkOut(const VoxelizeCommandOptions& options) {
  if (options.out.empty()) return;
  geo::refuseOverwritingInputs({options.out, geo::densityPathFor(options.out)},
                               options.bone.inputFiles());
  std::string ext = std::filesystem::path(options.out).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".nrrd" && ext != ".nhdr") {
    throw InputError(
        "--out " + options.out +
        ": the grid is written as NRRD, so the name must end in .nrrd (or .nhdr), not " +
        (ext.empty() ? std::string("nothing") : "'" + ext + "'"));
  }
}

geo::VoxelizeOptions voxelizeOptions(const VoxelizeCommandOptions& options,
                                     const sim::BoneMesh& loaded) {
  geo::VoxelizeOptions vo;
  vo.voxelSizeMm = options.bone.voxelSizeMm.value_or(0.0);
  vo.meshName = options.bone.input;
  vo.loadScaleToMm = loaded.read.scaleToMm;
  vo.raysPerAxis = options.raysPerAxis;
  vo.robust = options.robust;
  vo.density.corticalThicknessMm = options.corticalMm;
  const auto toDensity = [](int value, const char* flag) {
    if (value <= 0 || value > std::numeric_limits<geo::Density>::max()) {
      throw InputError(std::string(flag) + " " + std::to_string(value) +
                       ": must be an integer in 1..32767");
    }
    return geo::Density(value);
  };
  vo.density.corticalDensity = toDensity(options.corticalDensity, "--cortical-density");
  vo.density.cancellousDensity = toDensity(options.cancellousDensity, "--cancellous-density");
  return vo;
}

json toJson(const VoxelizeReport& r) {
  const VoxelizeCommandOptions& o = *r.options;
  const geo::VoxelizeStats& stats = r.stats;
  json j;
  j["mesh"] = meshJson(o.bone.input, r.loaded);
  j["dims"] = ivec3Json(r.grid.dims());
  j["voxel_size_mm"] = r.grid.voxelSizeMm();
  j["origin_mm"] = vec3Json(r.grid.originMm());
  j["voxels_inside"] = r.inside;
  j["voxels_nonempty"] = r.touched;
  j["bricks_allocated"] = r.grid.allocatedBrickCount();
  j["bricks_total"] = r.grid.brickCount();
  j["memory_bytes"] = r.grid.memoryBytes();
  j["volume_mm3"] = r.volumeMm3;
  j["mesh_volume_mm3"] = r.meshVolumeMm3;
  j["volume_error_percent"] = r.errorPercent;
  j["robust"] = o.robust;
  j["disagreeing_voxels"] = stats.disagreeingVoxels;
  j["abstained_columns"] = stats.abstainedColumns;
  j["rays"] = {{"per_column", o.raysPerAxis * o.raysPerAxis},
               {"cast", stats.raysCast},
               {"retried", stats.raysRetried},
               {"unresolved", stats.raysUnresolved},
               {"winding", stats.raysWinding},
               {"oriented_mesh", stats.orientedMesh}};
  j["density"] = {{"cortical_mm", r.voxelizing.density.corticalThicknessMm},
                  {"cortical_density", r.voxelizing.density.corticalDensity},
                  {"cancellous_density", r.voxelizing.density.cancellousDensity},
                  {"cortical_voxels", stats.density.corticalVoxels},
                  {"cancellous_voxels", stats.density.cancellousVoxels},
                  {"distance_queries", stats.density.distanceQueries}};
  j["time_ms"] = stats.totalMs;
  j["timings_ms"] = {{"load", r.loaded.read.loadMs}, {"bvh", stats.bvhMs},
                     {"rays", stats.raysMs},         {"combine", stats.combineMs},
                     {"density", stats.densityMs},   {"write", r.writeMs}};
  j["setup_ms"] = setupJson(r.setup);
  j["peak_rss_mb"] = peakRssMb();
  if (!o.out.empty()) {
    j["out"] = o.out;
    j["out_density"] = geo::densityPathFor(o.out);
  }
  if (r.inside == 0) {
    j["empty"] = true;
    j["empty_reason"] = "no voxel inside";
  }
  return j;
}

using ull = unsigned long long;

void printText(const VoxelizeReport& r) {
  const VoxelizeCommandOptions& o = *r.options;
  const geo::VoxelizeStats& stats = r.stats;
  const glm::ivec3 d = r.grid.dims();
  std::printf("osteon voxelize %s at %.4g mm%s\n", o.bone.input.c_str(), r.grid.voxelSizeMm(),
              o.robust ? " (robust: 3 axes, majority vote)" : "");
  std::printf("  mesh          %zu triangles, volume %.1f mm^3\n", r.loaded.mesh.triangleCount(),
              r.meshVolumeMm3);
  std::printf("  grid          %d x %d x %d voxels, %zu of %zu bricks allocated, %.2f MB\n", d.x,
              d.y, d.z, r.grid.allocatedBrickCount(), r.grid.brickCount(),
              double(r.grid.memoryBytes()) / 1e6);
  std::printf("  inside        %llu voxels (fill >= 1/2), %llu non-empty\n", ull(r.inside),
              ull(r.touched));
  std::printf("  volume        %.1f mm^3 (%+.3f %% vs mesh)\n", r.volumeMm3, r.errorPercent);
  std::printf("  density       %llu cortical (d=%d, within %.3g mm), %llu cancellous (d=%d)\n",
              ull(stats.density.corticalVoxels), r.voxelizing.density.corticalDensity,
              r.voxelizing.density.corticalThicknessMm, ull(stats.density.cancellousVoxels),
              r.voxelizing.density.cancellousDensity);
  std::printf("  rays          %llu cast, %llu retried, %llu unresolved\n", ull(stats.raysCast),
              ull(stats.raysRetried), ull(stats.raysUnresolved));
  if (o.robust) {
    std::printf("  robust vote   %llu disagreeing voxels, %llu abstained columns\n",
                ull(stats.disagreeingVoxels), ull(stats.abstainedColumns));
  }
  std::printf("  time          %.1f ms (bvh %.1f, rays %.1f, density %.1f); load %.1f ms\n",
              stats.totalMs, stats.bvhMs, stats.raysMs, stats.densityMs, r.loaded.read.loadMs);
  std::printf("%s\n", setupLine(r.setup).c_str());
  if (!o.out.empty())
    std::printf("  wrote         %s and %s\n", o.out.c_str(), geo::densityPathFor(o.out).c_str());
}

}  // namespace

int runVoxelize(const VoxelizeCommandOptions& options) {
  checkOut(options);
  VoxelizeReport r;
  r.options = &options;
  const Clock::time_point setupStart = Clock::now();
  r.loaded = sim::loadBoneMesh(options.bone);
  r.voxelizing = voxelizeOptions(options, r.loaded);
  r.grid = geo::voxelize(r.loaded.mesh, r.voxelizing, &r.stats);
  // Set-up ends with the grid (writing it is output, not set-up).
  r.setup.loadMs = r.loaded.read.loadMs;
  r.setup.voxelizeMs = std::max(0.0, r.stats.totalMs - r.stats.densityMs);
  r.setup.densityMs = r.stats.densityMs;
  r.setup.totalMs = msSince(setupStart);
  if (!options.out.empty()) {
    const Clock::time_point start = Clock::now();
    geo::writeNrrd(r.grid, options.out);
    r.writeMs = msSince(start);
  }
  r.meshVolumeMm3 = geo::signedVolumeMm3(r.loaded.mesh);
  r.volumeMm3 = r.grid.filledVolumeMm3();
  r.errorPercent = r.meshVolumeMm3 != 0.0 ? 100.0 * (r.volumeMm3 - std::abs(r.meshVolumeMm3)) /
                                                std::abs(r.meshVolumeMm3)
                                          : 0.0;
  r.inside = r.grid.countVoxels(geo::kFillHalf);
  r.touched = r.grid.countVoxels(1);
  printReport(r, options.json);
  if (r.inside == 0)
    return emptyExit("voxelize", options.bone.input, "no voxel inside", options.allowEmpty);
  return kExitOk;
}

}  // namespace osteon::cli
