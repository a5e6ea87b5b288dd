#include "commands/info.h"

#include <cstdio>

#include "osteon/core/error.h"
#include "osteon/geometry/io/dicom_series.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/volume_io.h"
#include "osteon/simulation/session.h"
#include "support/mesh_json.h"
#include "support/output.h"
#include "support/volume_report.h"

namespace osteon::cli {

namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

struct InfoReport {
  std::string input;
  bool builtIn = false;
  sim::BoneMesh loaded;
  geo::Aabb box;
  geo::MeshTopology topology;
  double volumeMm3 = 0.0, areaMm2 = 0.0;
};

json toJson(const InfoReport& r) {
  const geo::MeshTopology& topo = r.topology;
  json j = meshJson(r.input, r.loaded);
  j["bounds_min_mm"] = vec3Json(r.box.minMm);
  j["bounds_max_mm"] = vec3Json(r.box.maxMm);
  j["extent_mm"] = vec3Json(r.box.extentMm());
  j["volume_mm3"] = r.volumeMm3;
  j["area_mm2"] = r.areaMm2;
  j["edges"] = topo.edges;
  j["border_edges"] = topo.borderEdges;
  j["non_manifold_edges"] = topo.nonManifoldEdges;
  j["misoriented_edges"] = topo.misorientedEdges;
  j["degenerate_triangles"] = topo.degenerateTriangles;
  j["components"] = topo.components;
  j["euler_characteristic"] = topo.eulerCharacteristic;
  j["closed"] = topo.closed();
  j["consistently_oriented"] = topo.consistentlyOriented();
  j["load_ms"] = r.loaded.read.loadMs;
  return j;
}

void printText(const InfoReport& r) {
  const geo::MeshTopology& topo = r.topology;
  const glm::dvec3 e = r.box.extentMm();
  std::printf("%s: %zu vertices, %zu triangles", r.input.c_str(), r.loaded.mesh.vertexCount(),
              r.loaded.mesh.triangleCount());
  if (!r.builtIn) {
    std::printf(" (%s %s)", r.loaded.read.meshFile.binary ? "binary" : "text",
                geo::meshFormatName(r.loaded.read.meshFile.format));
  }
  std::printf("\n  extent     %.3f x %.3f x %.3f mm\n", e.x, e.y, e.z);
  std::printf("  bounds     [%.3f, %.3f, %.3f] .. [%.3f, %.3f, %.3f] mm\n", r.box.minMm.x,
              r.box.minMm.y, r.box.minMm.z, r.box.maxMm.x, r.box.maxMm.y, r.box.maxMm.z);
  std::printf("  volume     %.3f mm^3   area %.3f mm^2\n", r.volumeMm3, r.areaMm2);
  std::printf(
      "  topology   %s, %s; %zu border, %zu non-manifold, %zu misoriented edges; "
      "%zu component(s); Euler characteristic %lld\n",
      topo.closed() ? "closed" : "open",
      topo.consistentlyOriented() ? "consistently oriented" : "inconsistently oriented",
      topo.borderEdges, topo.nonManifoldEdges, topo.misorientedEdges, topo.components,
      topo.eulerCharacteristic);
}

// A DICOM folder: its series, and which one a volume command reads by default.
int runDicomInfo(const InfoOptions& options) {
  const std::string& input = options.bone.input;
  const std::vector<geo::DicomSeries> all = geo::listDicomSeries(input);
  const int chosen = geo::defaultDicomSeries(all);
  if (options.json) {
    json series = json::array();
    for (std::size_t i = 0; i < all.size(); ++i) {
      series.push_back({{"uid", all[i].uid},
                        {"slices", all[i].slices},
                        {"description", all[i].description},
                        {"default", int(i) == chosen}});
    }
    printJson(json{{"input", input}, {"format", "dicom"}, {"series", series}});
    return kExitOk;
  }
  std::printf("%s: DICOM, %zu series%s\n", input.c_str(), all.size(),
              chosen < 0 ? " (several of the largest size: pick one with --series UID)" : "");
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::printf("  series     %s: %d slice%s%s%s%s\n", all[i].uid.c_str(), all[i].slices,
                all[i].slices == 1 ? "" : "s", all[i].description.empty() ? "" : ", ",
                all[i].description.c_str(), int(i) == chosen ? " (read by default)" : "");
  }
  return kExitOk;
}

// A volume file: what it is read as, where it lies, and the bone it holds, as the commands that
// open it would read it (the same options).
int runVolumeInfo(const InfoOptions& options) {
  const sim::OpenedBone opened = sim::BoneModel::open(options.bone);
  const geo::VoxelGrid& grid = opened.bone->grid();
  const glm::ivec3 dims = grid.dims();
  const std::uint64_t inside = grid.countVoxels(geo::kFillHalf);
  const geo::VolumeLoad& volume = *opened.read.volume;
  if (options.json) {
    printJson(json{{"input", options.bone.input},
                   {"volume", volumeJson(volume, options.bone.volume)},
                   {"grid",
                    {{"dims", {dims.x, dims.y, dims.z}},
                     {"voxel_size_mm", grid.voxelSizeMm()},
                     {"origin_mm", vec3Json(grid.originMm())}}},
                   {"voxels_inside", inside},
                   {"load_ms", opened.read.loadMs}});
    return kExitOk;
  }
  const std::string line = volumeLine(volume, options.bone.volume);
  std::printf("%s: %d x %d x %d voxels of %g mm, %llu inside the bone\n%s%s",
              options.bone.input.c_str(), dims.x, dims.y, dims.z, grid.voxelSizeMm(),
              static_cast<unsigned long long>(inside), line.c_str(), line.empty() ? "" : "\n");
  return kExitOk;
}

}  // namespace

int runInfo(const InfoOptions& options) {
  if (options.bone.isVolume() && geo::volumeFormat(options.bone.input) == "dicom" &&
      options.bone.volume.series.empty())
    return runDicomInfo(options);
  if (options.bone.isVolume()) return runVolumeInfo(options);
  InfoReport r;
  r.input = options.bone.input;
  r.builtIn = options.bone.isBuiltIn();
  r.loaded = sim::loadBoneMesh(options.bone);
  r.box = geo::bounds(r.loaded.mesh);
  r.topology = geo::analyzeTopology(r.loaded.mesh);
  r.volumeMm3 = geo::signedVolumeMm3(r.loaded.mesh);
  r.areaMm2 = geo::surfaceAreaMm2(r.loaded.mesh);
  printReport(r, options.json);
  return kExitOk;
}

}  // namespace osteon::cli
