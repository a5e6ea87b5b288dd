#include "commands/mesh.h"

#include <cstdio>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/surface/surface.h"
#include "support/grid_input.h"
#include "support/output.h"

namespace osteon::cli {

namespace geo = osteon::geometry;
using nlohmann::json;

namespace {

struct MeshReport {
  const MeshCommandOptions* options = nullptr;
  LoadedGrid loaded;
  geo::SurfaceTimings timings;
  geo::SurfaceMesh surface;
  geo::TriangleMesh mesh;
  geo::MeshTopology topology;
};

geo::SurfaceOptions surfaceOptions(const MeshCommandOptions& options) {
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
  return so;
}

std::string emptyReason(const geo::VoxelGrid& grid) {
  return grid.countVoxels(geo::kFillHalf) == 0 ? "no triangles (no voxel inside)" : "no triangles";
}

json toJson(const MeshReport& r) {
  const MeshCommandOptions& o = *r.options;
  const geo::VoxelGrid& grid = r.loaded.bone->grid();
  const geo::MeshTopology& topo = r.topology;
  const geo::SurfaceTimings& t = r.timings;
  json j = {{"input", o.bone.input},
            {"method", o.method},
            {"voxel_size_mm", grid.voxelSizeMm()},
            {"voxels_inside", grid.countVoxels(geo::kFillHalf)},
            {"smooth", o.smooth},
            {"taubin", o.taubin},
            {"vertices", r.surface.vertexCount()},
            {"triangles", r.surface.triangleCount()},
            {"border_edges", topo.borderEdges},
            {"non_manifold_edges", topo.nonManifoldEdges},
            {"non_manifold_vertices", topo.nonManifoldVertices},
            {"misoriented_edges", topo.misorientedEdges},
            {"degenerate_triangles", topo.degenerateTriangles},
            {"components", topo.components},
            {"euler_characteristic", topo.eulerCharacteristic},
            {"volume_mm3", geo::signedVolumeMm3(r.mesh)},
            {"grid_volume_mm3", grid.filledVolumeMm3()},
            {"time_ms",
             {{"total", t.totalMs},
              {"extract", t.extractMs},
              {"smooth", t.smoothMs},
              {"normals", t.normalsMs},
              {"other", t.otherMs}}},
            {"voxelize_ms", r.loaded.voxelizeMs},
            {"setup_ms", setupJson(r.loaded.setup)},
            {"peak_rss_mb", peakRssMb()}};
  if (!o.out.empty()) j["out"] = o.out;
  if (!r.loaded.volume.is_null()) j["volume"] = r.loaded.volume;
  if (r.surface.triangleCount() == 0) {
    j["empty"] = true;
    j["empty_reason"] = emptyReason(grid);
  }
  return j;
}

void printText(const MeshReport& r) {
  const MeshCommandOptions& o = *r.options;
  const geo::VoxelGrid& grid = r.loaded.bone->grid();
  const geo::MeshTopology& topo = r.topology;
  const geo::SurfaceTimings& t = r.timings;
  std::printf("osteon mesh %s (%s, %d smoothing passes%s) at %.4g mm\n", o.bone.input.c_str(),
              o.method.c_str(), o.smooth, o.taubin ? ", Taubin" : "", grid.voxelSizeMm());
  std::printf("  surface     %zu vertices, %zu triangles, %.1f mm^3 (grid %.1f mm^3)\n",
              r.surface.vertexCount(), r.surface.triangleCount(), geo::signedVolumeMm3(r.mesh),
              grid.filledVolumeMm3());
  std::printf(
      "  topology    %zu border edges, %zu non-manifold edges, %zu pinched vertices, "
      "%zu component(s), Euler characteristic %lld\n",
      topo.borderEdges, topo.nonManifoldEdges, topo.nonManifoldVertices, topo.components,
      topo.eulerCharacteristic);
  std::printf("  time        %.2f ms: extract %.2f, smooth %.2f, normals %.2f, other %.2f\n",
              t.totalMs, t.extractMs, t.smoothMs, t.normalsMs, t.otherMs);
  std::printf("%s\n", setupLine(r.loaded.setup).c_str());
  if (!r.loaded.volumeText.empty()) std::printf("%s\n", r.loaded.volumeText.c_str());
  if (!o.out.empty()) std::printf("  wrote       %s\n", o.out.c_str());
}

}  // namespace

int runMesh(const MeshCommandOptions& options) {
  const geo::SurfaceOptions so = surfaceOptions(options);
  if (!options.out.empty()) {
    geo::meshFormatFromPath(options.out);  // fail before the work
    geo::refuseOverwritingInputs({options.out}, options.bone.inputFiles());
  }
  MeshReport r;
  r.options = &options;
  r.loaded = loadGrid(options.bone);
  const geo::VoxelGrid& grid = r.loaded.bone->grid();
  const Clock::time_point surfaceStart = Clock::now();
  r.surface = geo::extractSurface(grid, so, &r.timings);
  r.loaded.setup.surfaceMs = msSince(surfaceStart);
  // Set-up ends with the surface; topology and writing are not part of it.
  r.loaded.setup.totalMs = msSince(r.loaded.start);
  r.loaded.setup.surfaceReadyMs = r.loaded.setup.totalMs;  // extracted before anything else
  r.mesh = r.surface.toTriangleMesh();
  r.topology = geo::analyzeTopology(r.mesh);
  if (!options.out.empty()) geo::writeMesh(r.mesh, options.out);
  printReport(r, options.json);
  if (r.surface.triangleCount() == 0) {
    return emptyExit("mesh", options.bone.input, emptyReason(grid), options.allowEmpty);
  }
  return kExitOk;
}

}  // namespace osteon::cli
