// The work behind each `osteon` command, and its JSON (nlohmann/json lives in this file only).
#include "commands.h"
#include "run_summary.h"
#include "osteon/core/memory.h"
#include "osteon/core/timing.h"

#include "hierarchy_svg.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/mesh_source.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/volume_io.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/io/units.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/session.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <filesystem>
#include <algorithm>
#include <limits>
#include <sstream>

namespace osteon::cli {

namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {


json vec3(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }
json ivec3(const glm::ivec3& v) { return json::array({v.x, v.y, v.z}); }

// Paths are bytes, not always UTF-8: invalid sequences print as U+FFFD rather than failing.
void printJson(const json& j) {
  std::cout << j.dump(2, ' ', false, json::error_handler_t::replace) << "\n";
}

json meshJson(const std::string& argument, const sim::BoneMesh& loaded) {
  const bool builtIn = argument == geo::kDefaultModelArgument;
  json j = {{"path", argument},
            {"built_in", builtIn},
            {"scale_to_mm", loaded.read.scaleToMm},
            {"vertices", loaded.mesh.vertexCount()},
            {"triangles", loaded.mesh.triangleCount()}};
  if (!builtIn) {
    j["format"] = geo::meshFormatName(loaded.read.meshFile.format);
    j["binary"] = loaded.read.meshFile.binary;
    j["polygons_triangulated"] = loaded.read.meshFile.polygonsTriangulated;
    j["degenerate_faces_dropped"] = loaded.read.meshFile.degenerateDropped;
  }
  return j;
}

}  // namespace

int runInfo(const InfoOptions& options) {
  const sim::BoneMesh loaded = sim::loadBoneMesh(options.bone);
  const geo::Aabb box = geo::bounds(loaded.mesh);
  const geo::MeshTopology topo = geo::analyzeTopology(loaded.mesh);
  const double volume = geo::signedVolumeMm3(loaded.mesh);
  const double area = geo::surfaceAreaMm2(loaded.mesh);
  if (options.json) {
    json j = meshJson(options.bone.input, loaded);
    j["bounds_min_mm"] = vec3(box.minMm);
    j["bounds_max_mm"] = vec3(box.maxMm);
    j["extent_mm"] = vec3(box.extentMm());
    j["volume_mm3"] = volume;
    j["area_mm2"] = area;
    j["edges"] = topo.edges;
    j["border_edges"] = topo.borderEdges;
    j["non_manifold_edges"] = topo.nonManifoldEdges;
    j["misoriented_edges"] = topo.misorientedEdges;
    j["degenerate_triangles"] = topo.degenerateTriangles;
    j["components"] = topo.components;
    j["euler_characteristic"] = topo.eulerCharacteristic;
    j["closed"] = topo.closed();
    j["consistently_oriented"] = topo.consistentlyOriented();
    j["load_ms"] = loaded.read.loadMs;
    printJson(j);
    return kExitOk;
  }
  const glm::dvec3 e = box.extentMm();
  std::printf("%s: %zu vertices, %zu triangles", options.bone.input.c_str(), loaded.mesh.vertexCount(),
              loaded.mesh.triangleCount());
  if (!options.bone.isBuiltIn()) {
    std::printf(" (%s %s)", loaded.read.meshFile.binary ? "binary" : "text",
                geo::meshFormatName(loaded.read.meshFile.format));
  }
  std::printf("\n  extent     %.3f x %.3f x %.3f mm\n", e.x, e.y, e.z);
  std::printf("  bounds     [%.3f, %.3f, %.3f] .. [%.3f, %.3f, %.3f] mm\n", box.minMm.x,
              box.minMm.y, box.minMm.z, box.maxMm.x, box.maxMm.y, box.maxMm.z);
  std::printf("  volume     %.3f mm^3   area %.3f mm^2\n", volume, area);
  std::printf("  topology   %s, %s; %zu border, %zu non-manifold, %zu misoriented edges; "
              "%zu component(s); Euler characteristic %lld\n",
              topo.closed() ? "closed" : "open",
              topo.consistentlyOriented() ? "consistently oriented" : "inconsistently oriented",
              topo.borderEdges, topo.nonManifoldEdges, topo.misorientedEdges, topo.components,
              topo.eulerCharacteristic);
  return kExitOk;
}

int runVoxelize(const VoxelizeCommandOptions& options) {
  if (!options.out.empty()) {
    geo::refuseOverwritingInputs({options.out, geo::densityPathFor(options.out)}, options.bone.inputFiles());
    // The grid is written as NRRD whatever the name says: a name that promises a mesh or an
    // image would hold NRRD bytes.
    std::string ext = fs::path(options.out).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".nrrd" && ext != ".nhdr") {
      throw InputError("--out " + options.out + ": the grid is written as NRRD, so the name must end in .nrrd (or .nhdr), not " +
                       (ext.empty() ? std::string("nothing") : "'" + ext + "'"));
    }
  }
  const Clock::time_point setupStart = Clock::now();
  const sim::BoneMesh loaded = sim::loadBoneMesh(options.bone);
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

  geo::VoxelizeStats stats;
  const geo::VoxelGrid grid = geo::voxelize(loaded.mesh, vo, &stats);
  // Set-up ends with the grid (writing it is output, not set-up).
  sim::SetupTimings setup;
  setup.loadMs = loaded.read.loadMs;
  setup.voxelizeMs = std::max(0.0, stats.totalMs - stats.densityMs);
  setup.densityMs = stats.densityMs;
  setup.totalMs = msSince(setupStart);
  double writeMs = 0.0;
  if (!options.out.empty()) {
    const Clock::time_point start = Clock::now();
    geo::writeNrrd(grid, options.out);
    writeMs = msSince(start);
  }

  const double meshVolume = geo::signedVolumeMm3(loaded.mesh);
  const double volume = grid.filledVolumeMm3();
  const double errorPercent =
      meshVolume != 0.0 ? 100.0 * (volume - std::abs(meshVolume)) / std::abs(meshVolume) : 0.0;
  const std::uint64_t inside = grid.countVoxels(geo::kFillHalf);
  const std::uint64_t touched = grid.countVoxels(1);

  if (options.json) {
    json j;
    j["mesh"] = meshJson(options.bone.input, loaded);
    j["dims"] = ivec3(grid.dims());
    j["voxel_size_mm"] = grid.voxelSizeMm();
    j["origin_mm"] = vec3(grid.originMm());
    j["voxels_inside"] = inside;
    j["voxels_nonempty"] = touched;
    j["bricks_allocated"] = grid.allocatedBrickCount();
    j["bricks_total"] = grid.brickCount();
    j["memory_bytes"] = grid.memoryBytes();
    j["volume_mm3"] = volume;
    j["mesh_volume_mm3"] = meshVolume;
    j["volume_error_percent"] = errorPercent;
    j["robust"] = options.robust;
    j["disagreeing_voxels"] = stats.disagreeingVoxels;
    j["abstained_columns"] = stats.abstainedColumns;
    j["rays"] = {{"per_column", options.raysPerAxis * options.raysPerAxis},
                 {"cast", stats.raysCast},
                 {"retried", stats.raysRetried},
                 {"unresolved", stats.raysUnresolved},
                 {"winding", stats.raysWinding},
                 {"oriented_mesh", stats.orientedMesh}};
    j["density"] = {{"cortical_mm", vo.density.corticalThicknessMm},
                    {"cortical_density", vo.density.corticalDensity},
                    {"cancellous_density", vo.density.cancellousDensity},
                    {"cortical_voxels", stats.density.corticalVoxels},
                    {"cancellous_voxels", stats.density.cancellousVoxels},
                    {"distance_queries", stats.density.distanceQueries}};
    j["time_ms"] = stats.totalMs;
    j["timings_ms"] = {{"load", loaded.read.loadMs},   {"bvh", stats.bvhMs},
                       {"rays", stats.raysMs},    {"combine", stats.combineMs},
                       {"density", stats.densityMs}, {"write", writeMs}};
    j["setup_ms"] = setupJson(setup);
    j["peak_rss_mb"] = peakRssMb();
    if (!options.out.empty()) {
      j["out"] = options.out;
      j["out_density"] = geo::densityPathFor(options.out);
    }
    if (inside == 0) {
      j["empty"] = true;
      j["empty_reason"] = "no voxel inside";
    }
    printJson(j);
    if (inside == 0) return emptyExit("voxelize", options.bone.input, "no voxel inside", options.allowEmpty);
    return kExitOk;
  }
  const glm::ivec3 d = grid.dims();
  std::printf("osteon voxelize %s at %.4g mm%s\n", options.bone.input.c_str(), grid.voxelSizeMm(),
              options.robust ? " (robust: 3 axes, majority vote)" : "");
  std::printf("  mesh          %zu triangles, volume %.1f mm^3\n", loaded.mesh.triangleCount(),
              meshVolume);
  std::printf("  grid          %d x %d x %d voxels, %zu of %zu bricks allocated, %.2f MB\n", d.x,
              d.y, d.z, grid.allocatedBrickCount(), grid.brickCount(),
              double(grid.memoryBytes()) / 1e6);
  std::printf("  inside        %llu voxels (fill >= 1/2), %llu non-empty\n",
              static_cast<unsigned long long>(inside), static_cast<unsigned long long>(touched));
  std::printf("  volume        %.1f mm^3 (%+.3f %% vs mesh)\n", volume, errorPercent);
  std::printf("  density       %llu cortical (d=%d, within %.3g mm), %llu cancellous (d=%d)\n",
              static_cast<unsigned long long>(stats.density.corticalVoxels),
              vo.density.corticalDensity, vo.density.corticalThicknessMm,
              static_cast<unsigned long long>(stats.density.cancellousVoxels),
              vo.density.cancellousDensity);
  std::printf("  rays          %llu cast, %llu retried, %llu unresolved\n",
              static_cast<unsigned long long>(stats.raysCast),
              static_cast<unsigned long long>(stats.raysRetried),
              static_cast<unsigned long long>(stats.raysUnresolved));
  if (options.robust) {
    std::printf("  robust vote   %llu disagreeing voxels, %llu abstained columns\n",
                static_cast<unsigned long long>(stats.disagreeingVoxels),
                static_cast<unsigned long long>(stats.abstainedColumns));
  }
  std::printf("  time          %.1f ms (bvh %.1f, rays %.1f, density %.1f); load %.1f ms\n",
              stats.totalMs, stats.bvhMs, stats.raysMs, stats.densityMs, loaded.read.loadMs);
  std::printf("%s\n", setupLine(setup).c_str());
  if (!options.out.empty()) {
    std::printf("  wrote         %s and %s\n", options.out.c_str(),
                geo::densityPathFor(options.out).c_str());
  }
  if (inside == 0) return emptyExit("voxelize", options.bone.input, "no voxel inside", options.allowEmpty);
  return kExitOk;
}

int runModel(const ModelOptions& options) {
  const Clock::time_point start = Clock::now();
  const geo::HumerusModel model = geo::buildHumerusModel();
  const double buildMs = msSince(start);
  if (!options.out.empty()) geo::writeMesh(model.mesh, options.out);
  const geo::MeshTopology topo = geo::analyzeTopology(model.mesh);
  if (options.json) {
    json j = {{"vertices", model.mesh.vertexCount()},
              {"triangles", model.mesh.triangleCount()},
              {"volume_mm3", geo::signedVolumeMm3(model.mesh)},
              {"head_centre_mm", vec3(model.headCentreMm)},
              {"head_radius_mm", model.headRadiusMm},
              {"head_axis", vec3(model.headAxis)},
              {"shaft_axis", vec3(model.shaftAxis)},
              {"closed", topo.closed()},
              {"euler_characteristic", topo.eulerCharacteristic},
              {"build_ms", buildMs}};
    if (!options.out.empty()) j["out"] = options.out;
    printJson(j);
    return kExitOk;
  }
  std::printf("built-in right proximal humerus: %zu vertices, %zu triangles, %.1f mm^3, %s\n",
              model.mesh.vertexCount(), model.mesh.triangleCount(),
              geo::signedVolumeMm3(model.mesh), topo.closed() ? "closed" : "OPEN");
  std::printf("  head centre (%.3f, %.3f, %.3f) mm, radius %.3f mm, axis (%.4f, %.4f, %.4f)\n",
              model.headCentreMm.x, model.headCentreMm.y, model.headCentreMm.z,
              model.headRadiusMm, model.headAxis.x, model.headAxis.y, model.headAxis.z);
  if (!options.out.empty()) std::printf("  wrote %s\n", options.out.c_str());
  return kExitOk;
}

// What a volume was read as, for the JSON ("volume") and the text output (one line).
json volumeJson(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning) {
  json j = {{"kind", v.kind}, {"format", v.format}, {"type", v.type}};
  if (v.kind == "osteon grid") {
    j["density_loaded"] = v.densityLoaded;
    return j;
  }
  j["min"] = v.minValue;
  j["max"] = v.maxValue;
  if (v.kind == "label map") {
    // Labels as integers, exact to 64 bits (a uint64 label past 2^63 too), not as doubles.
    j["min"] = v.labels.front();
    j["max"] = v.labels.back();
    j["labels"] = v.labels;
    j["background"] = v.background;
    j["bone_label"] = v.label ? json(*v.label) : json(v.background == 0 ? "every non-zero" : "every non-background");
  } else {
    j["iso_hu"] = v.isoHu;
    j["iso_default"] = !meaning.isoHu.has_value();
    j["fill_ramp_hu"] = {v.isoHu - geo::kCtRampHalfWidthHu, v.isoHu + geo::kCtRampHalfWidthHu};
    j["cortical_from_hu"] = geo::kCorticalHu;
  }
  return j;
}

std::string volumeLine(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning) {
  if (v.kind == "osteon grid") return "";  // osteon's own grids: the output as it always was
  std::ostringstream s;
  s << "  volume      " << v.format << " " << v.type << ", read as " << v.kind;
  if (v.kind == "label map") {
    s << " (labels";
    for (std::uint64_t l : v.labels) s << " " << l;
    s << "; bone: "
      << (v.label ? "label " + std::to_string(*v.label)
                  : v.background == 0 ? std::string("every non-zero voxel")
                                      : "every voxel but the background " + std::to_string(v.background) +
                                            " (0 absent: the most common value)")
      << ")";
  } else if (v.kind == "ct") {
    s << " (values " << v.minValue << " to " << v.maxValue << "; iso " << v.isoHu << " HU"
      << (meaning.isoHu ? "" : " (default)") << ", cortical from " << geo::kCorticalHu << " HU)";
  }
  return s.str();
}

// An empty result: said on stderr; exit 1 unless --allow-empty.
int emptyExit(const char* command, const std::string& input, const std::string& reason, bool allowEmpty) {
  std::fprintf(stderr, "osteon %s: %s: empty result: %s%s\n", command, input.c_str(), reason.c_str(),
               allowEmpty ? " (accepted: --allow-empty)" : " (exit 1; --allow-empty accepts it)");
  return allowEmpty ? kExitOk : kExitCheckFailed;
}

// Refuses inputs inside a folder the run fills with files of its own naming.
void refuseInputsInside(const std::string& folder, const std::vector<std::string>& inputs) {
  std::error_code ec;
  const fs::path dir = fs::weakly_canonical(folder, ec);
  if (ec) return;
  for (const std::string& in : inputs) {
    if (in.empty() || !fs::exists(in, ec)) continue;
    const fs::path file = fs::canonical(in, ec);
    if (ec) continue;
    const auto mismatch = std::mismatch(dir.begin(), dir.end(), file.begin(), file.end());
    if (mismatch.first == dir.end()) {
      throw InputError(in + ": is inside " + folder + ", which this run fills with its own files "
                       "(refusing to risk overwriting an input; choose another --out-dir)");
    }
  }
}

namespace {

// The grid a command works on, what it was read from, and its set-up so far.
struct LoadedGrid {
  Clock::time_point start = Clock::now();  // the command's set-up starts here
  std::shared_ptr<const sim::BoneModel> bone;
  double voxelizeMs = 0.0;
  json volume;              // a volume's meaning, null for a mesh
  std::string volumeText;
  sim::SetupTimings setup;  // a volume's whole read, its density included, is its load
};

// A GRID.nrrd or other volume as read, or a mesh voxelized at --voxel-size: the bone as it is,
// empty or not (the commands report an empty result), without a session's fine fills.
LoadedGrid loadGrid(BoneSource source) {
  LoadedGrid out;
  source.forSession = false;
  source.sampleFineFills = false;
  sim::OpenedBone opened = sim::BoneModel::open(source);
  out.bone = std::move(opened.bone);
  out.setup = out.bone->setupTimings();
  out.voxelizeMs = out.setup.voxelizeMs + out.setup.densityMs;
  if (opened.read.volume) {
    out.volume = volumeJson(*opened.read.volume, source.volume);
    out.volumeText = volumeLine(*opened.read.volume, source.volume);
  }
  return out;
}

}  // namespace

int runHierarchy(const HierarchyOptions& options) {
  if (!options.svg.empty()) geo::refuseOverwritingInputs({options.svg}, options.bone.inputFiles());
  LoadedGrid loaded = loadGrid(options.bone);
  const geo::VoxelGrid& grid = loaded.bone->grid();
  sim::SetupTimings& setup = loaded.setup;
  geo::DphBuildOptions build;
  build.expansionRatio = options.xi;
  build.seed = options.seed;
  const Clock::time_point start = Clock::now();
  const geo::DynamicProximityHierarchy hierarchy = geo::DynamicProximityHierarchy::build(grid, build);
  const double buildMs = msSince(start);
  setup.hierarchyMs = buildMs;
  setup.totalMs = msSince(loaded.start);  // set-up ends with the hierarchy; the checks are not part of it
  const std::string problem = hierarchy.validateAgainst(grid);

  int sliceZ = grid.dims().z / 2;
  if (options.sliceZMm) {
    sliceZ = int(std::floor(grid.gridFromWorld(glm::dvec3(0.0, 0.0, *options.sliceZMm)).z));
    if (sliceZ < 0 || sliceZ >= grid.dims().z) {
      std::ostringstream s;
      s << "--slice-z " << *options.sliceZMm << ": outside the grid (z from "
        << grid.originMm().z << " to " << grid.worldFromGrid(glm::dvec3(grid.dims())).z << " mm)";
      throw InputError(s.str());
    }
  }
  if (!options.svg.empty()) {
    std::ostringstream title;
    title << "DPH of " << options.bone.input << ", xi " << options.xi << ", voxel "
          << grid.voxelSizeMm() << " mm";
    writeHierarchySvg(hierarchy, grid, sliceZ, title.str(), options.svg);
  }

  json levels = json::array();
  for (int level = 0; level < hierarchy.levelCount(); ++level) {
    levels.push_back({{"level", level},
                      {"nodes", hierarchy.nodeCount(level)},
                      {"cell_voxels", 2 * hierarchy.halfWidth(level) + 1}});
  }
  if (options.json) {
    json j = {{"input", options.bone.input},
              {"voxel_size_mm", grid.voxelSizeMm()},
              {"dims", ivec3(grid.dims())},
              {"xi", options.xi},
              {"seed", options.seed},
              {"voxels", hierarchy.voxelCount()},
              {"levels", hierarchy.levelCount()},
              {"nodes_per_level", levels},
              {"build_ms", buildMs},
              {"voxelize_ms", loaded.voxelizeMs},
              {"memory_bytes", hierarchy.memoryBytes()},
              {"valid", problem.empty()},
              {"setup_ms", setupJson(setup)},
              {"peak_rss_mb", peakRssMb()}};
    if (!problem.empty()) j["problem"] = problem;
    if (!loaded.volume.is_null()) j["volume"] = loaded.volume;
    if (hierarchy.voxelCount() == 0) {
      j["empty"] = true;
      j["empty_reason"] = "no voxel inside";
    }
    if (!options.svg.empty()) j["svg"] = options.svg;
    printJson(j);
  } else {
    std::printf("osteon hierarchy %s: %zu voxels at %.4g mm, xi %d, seed %llu\n",
                options.bone.input.c_str(), hierarchy.voxelCount(), grid.voxelSizeMm(), options.xi,
                static_cast<unsigned long long>(options.seed));
    for (int level = 0; level < hierarchy.levelCount(); ++level) {
      std::printf("  level %2d  %9zu nodes   cells of %lld voxels\n", level,
                  hierarchy.nodeCount(level), 2 * hierarchy.halfWidth(level) + 1);
    }
    std::printf("  build %.1f ms, %.2f MB; %s\n", buildMs, double(hierarchy.memoryBytes()) / 1e6,
                problem.empty() ? "all invariants hold" : problem.c_str());
    std::printf("%s\n", setupLine(setup).c_str());
    if (!loaded.volumeText.empty()) std::printf("%s\n", loaded.volumeText.c_str());
    if (!options.svg.empty()) std::printf("  wrote %s (slice z = %d)\n", options.svg.c_str(), sliceZ);
  }
  if (!problem.empty()) return kExitCheckFailed;
  if (hierarchy.voxelCount() == 0) return emptyExit("hierarchy", options.bone.input, "no voxel inside", options.allowEmpty);
  return kExitOk;
}

namespace {

std::string emptyMeshReason(const geo::VoxelGrid& grid) {
  return grid.countVoxels(geo::kFillHalf) == 0 ? "no triangles (no voxel inside)" : "no triangles";
}

}  // namespace

int runMesh(const MeshCommandOptions& options) {
  geo::SurfaceOptions so;
  if (options.method == "crackfree") {
    so.method = geo::SurfaceMethod::CrackFree;
  } else if (options.method == "naive") {
    so.method = geo::SurfaceMethod::Naive;
  } else {
    throw InputError("--method " + options.method + ": unknown (expected crackfree or naive)");
  }
  so.smoothIterations = options.smooth;
  so.taubin = options.taubin;
  if (!options.out.empty()) {
    geo::meshFormatFromPath(options.out);  // fail before the work
    geo::refuseOverwritingInputs({options.out}, options.bone.inputFiles());
  }
  LoadedGrid loaded = loadGrid(options.bone);
  const geo::VoxelGrid& grid = loaded.bone->grid();
  sim::SetupTimings& setup = loaded.setup;
  geo::SurfaceTimings t;
  const Clock::time_point surfaceStart = Clock::now();
  const geo::SurfaceMesh surface = geo::extractSurface(grid, so, &t);
  setup.surfaceMs = msSince(surfaceStart);
  setup.totalMs = msSince(loaded.start);  // set-up ends with the surface; topology and writing are not part of it
  const geo::TriangleMesh mesh = surface.toTriangleMesh();
  const geo::MeshTopology topo = geo::analyzeTopology(mesh);
  if (!options.out.empty()) geo::writeMesh(mesh, options.out);
  if (options.json) {
    json j = {{"input", options.bone.input},
              {"method", options.method},
              {"voxel_size_mm", grid.voxelSizeMm()},
              {"voxels_inside", grid.countVoxels(geo::kFillHalf)},
              {"smooth", options.smooth},
              {"taubin", options.taubin},
              {"vertices", surface.vertexCount()},
              {"triangles", surface.triangleCount()},
              {"border_edges", topo.borderEdges},
              {"non_manifold_edges", topo.nonManifoldEdges},
              {"non_manifold_vertices", topo.nonManifoldVertices},
              {"misoriented_edges", topo.misorientedEdges},
              {"degenerate_triangles", topo.degenerateTriangles},
              {"components", topo.components},
              {"euler_characteristic", topo.eulerCharacteristic},
              {"volume_mm3", geo::signedVolumeMm3(mesh)},
              {"grid_volume_mm3", grid.filledVolumeMm3()},
              {"time_ms",
               {{"total", t.totalMs}, {"extract", t.extractMs}, {"smooth", t.smoothMs},
                {"normals", t.normalsMs}, {"other", t.otherMs}}},
              {"voxelize_ms", loaded.voxelizeMs},
              {"setup_ms", setupJson(setup)},
              {"peak_rss_mb", peakRssMb()}};
    if (!options.out.empty()) j["out"] = options.out;
    if (!loaded.volume.is_null()) j["volume"] = loaded.volume;
    if (surface.triangleCount() == 0) {
      j["empty"] = true;
      j["empty_reason"] = emptyMeshReason(grid);
    }
    printJson(j);
    if (surface.triangleCount() == 0) return emptyExit("mesh", options.bone.input, emptyMeshReason(grid), options.allowEmpty);
    return kExitOk;
  }
  std::printf("osteon mesh %s (%s, %d smoothing passes%s) at %.4g mm\n", options.bone.input.c_str(),
              options.method.c_str(), options.smooth, options.taubin ? ", Taubin" : "",
              grid.voxelSizeMm());
  std::printf("  surface     %zu vertices, %zu triangles, %.1f mm^3 (grid %.1f mm^3)\n",
              surface.vertexCount(), surface.triangleCount(), geo::signedVolumeMm3(mesh),
              grid.filledVolumeMm3());
  std::printf("  topology    %zu border edges, %zu non-manifold edges, %zu pinched vertices, "
              "%zu component(s), Euler characteristic %lld\n",
              topo.borderEdges, topo.nonManifoldEdges, topo.nonManifoldVertices, topo.components,
              topo.eulerCharacteristic);
  std::printf("  time        %.2f ms: extract %.2f, smooth %.2f, normals %.2f, other %.2f\n",
              t.totalMs, t.extractMs, t.smoothMs, t.normalsMs, t.otherMs);
  std::printf("%s\n", setupLine(setup).c_str());
  if (!loaded.volumeText.empty()) std::printf("%s\n", loaded.volumeText.c_str());
  if (!options.out.empty()) std::printf("  wrote       %s\n", options.out.c_str());
  if (surface.triangleCount() == 0) return emptyExit("mesh", options.bone.input, emptyMeshReason(grid), options.allowEmpty);
  return kExitOk;
}

}  // namespace osteon::cli
