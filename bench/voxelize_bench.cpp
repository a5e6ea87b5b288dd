// Voxelization (seed 3.2) of the built-in humerus and the shared fibula at 1.0 / 0.5 /
// 0.25 mm, single-axis and robust. Figures go into docs/performance.md.
#include <filesystem>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/voxels/voxelizer.h"

namespace {

using namespace osteon::geometry;

const TriangleMesh* meshNamed(const std::string& name) {
  static std::map<std::string, TriangleMesh> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return &it->second;
  if (name == "humerus_default") {
    return &cache.emplace(name, buildHumerusModel().mesh).first->second;
  }
  const std::string path = std::string(OSTEON_SHARED_DATA_DIR) + "/fibula_L_vhm_denver.stl";
  if (!std::filesystem::exists(path)) return nullptr;
  return &cache.emplace(name, readMesh(path)).first->second;
}

void voxelizeBench(benchmark::State& state, const std::string& model, bool robust) {
  const TriangleMesh* mesh = meshNamed(model);
  if (!mesh) {
    state.SkipWithError("shared data not found");
    return;
  }
  VoxelizeOptions options;
  options.voxelSizeMm = double(state.range(0)) / 1000.0;
  options.robust = robust;
  VoxelizeStats stats;
  std::size_t inside = 0, bricks = 0, memory = 0;
  for (auto _ : state) {
    VoxelGrid grid = voxelize(*mesh, options, &stats);
    inside = grid.countVoxels(kFillHalf);
    bricks = grid.allocatedBrickCount();
    memory = grid.memoryBytes();
    benchmark::DoNotOptimize(grid);
  }
  state.counters["voxels_inside"] = double(inside);
  state.counters["bricks_alloc"] = double(bricks);
  state.counters["grid_MB"] = double(memory) / 1e6;
  state.counters["rays_ms"] = stats.raysMs;
  state.counters["density_ms"] = stats.densityMs;
  state.counters["bvh_ms"] = stats.bvhMs;
  state.counters["triangles"] = double(mesh->triangleCount());
}

void registerAll() {
  for (const char* model : {"humerus_default", "fibula_shared"}) {
    for (bool robust : {false, true}) {
      const std::string name = std::string("voxelize/") + model + (robust ? "/robust" : "/z");
      benchmark::RegisterBenchmark(
          name.c_str(), [model, robust](benchmark::State& s) { voxelizeBench(s, model, robust); })
          ->Arg(1000)
          ->Arg(500)
          ->Arg(250)
          ->ArgName("voxel_um")
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  registerAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
