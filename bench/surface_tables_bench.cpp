// The surface benches' incremental update after one drilling step at 0.25 mm, and the seed's
// Tables 1 and 2 for the built-in and the shared humerus (surface_bench.cpp runs them).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/removal.h"

#ifdef OSTEON_HAVE_VTK
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkSmartPointer.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <malloc.h>
#include <map>
#include <memory>
#include <sys/resource.h>

#include "surface_bench.h"

namespace osteon::bench {

using namespace osteon::geometry;

namespace {

void report(benchmark::State& state, std::vector<double>& ms, const std::string& prefix) {
  if (ms.empty()) return;
  std::sort(ms.begin(), ms.end());
  const auto at = [&](double q) {
    return ms[std::min(ms.size() - 1, std::size_t(q * double(ms.size())))];
  };
  state.counters[prefix + "p50_ms"] = at(0.5);
  state.counters[prefix + "p99_ms"] = at(0.99);
  state.counters[prefix + "max_ms"] = ms.back();
  state.counters[prefix + "steps"] = double(ms.size());
}

// The built-in humerus at one voxel size, with a static drill (level 0) and the surface kept
// up to date.
struct DrillScene {
  VoxelGrid grid;
  DynamicProximityHierarchy hierarchy;
  std::unique_ptr<RefinedVoxels> refined;
  std::unique_ptr<osteon::simulation::MaterialRemoval> drill;
  std::unique_ptr<SurfaceUpdater> updater;

  explicit DrillScene(double voxelSizeMm) {
    VoxelizeOptions options;
    options.voxelSizeMm = voxelSizeMm;
    grid = voxelize(humerusModel().mesh, options);
    hierarchy = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
    RefinementOptions ro;
    ro.depth = 0;
    refined = std::make_unique<RefinedVoxels>(grid, hierarchy, nullptr, ro);
    drill = std::make_unique<osteon::simulation::MaterialRemoval>(*refined);
    updater = std::make_unique<SurfaceUpdater>(grid);
    grid.clearDirty();
  }
  SurfaceUpdater::UpdateStats updateSurface() {
    const std::vector<std::size_t> dirty = grid.dirtyBricks();
    grid.clearDirty();
    return updater->update(dirty);
  }
};

// One drilling step = one 1 ms haptic step of material removal (seed 3.5: every voxel inside
// the 2.92 mm tip loses one density unit, those at 0 go), then the surface update, smoothing
// and normals included. The drill enters the humeral head along its axis at 5 mm/s for 2 s.
void BM_IncrementalDrillStep(benchmark::State& state) {
  const double vs = double(state.range(0)) / 1000.0;
  std::vector<double> changed, all;
  std::size_t cellBricks = 0, steps = 0;
  for (auto _ : state) {
    state.PauseTiming();
    DrillScene scene(vs);
    const glm::dvec3 axis = humerusModel().headAxis;
    const glm::dvec3 start =
        humerusModel().headCentreMm + (humerusModel().headRadiusMm + 1.0) * axis;
    state.ResumeTiming();
    for (int step = 0; step < 2000; ++step) {
      const glm::dvec3 tip = start - axis * (0.005 * step);  // 5 um per 1 ms step
      scene.drill->removeInSphere(tip, 1.46, 1);
      const Clock::time_point t0 = Clock::now();
      const SurfaceUpdater::UpdateStats s = scene.updateSurface();
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
      all.push_back(ms);
      if (s.verticesTouched > 0) {
        changed.push_back(ms);
        cellBricks += s.cellBricks;
        ++steps;
      }
    }
  }
  report(state, all, "every_step_");
  report(state, changed, "changing_step_");
  state.counters["cell_bricks_per_changing_step"] =
      steps ? double(cellBricks) / double(steps) : 0.0;
}
BENCHMARK(BM_IncrementalDrillStep)
    ->Arg(250)
    ->Arg(540)
    ->ArgName("voxel_um")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// Worst case: the whole 2.92 mm sphere of bone removed at once at a new place every step.
void BM_IncrementalSphereRemoved(benchmark::State& state) {
  DrillScene scene(double(state.range(0)) / 1000.0);
  std::vector<double> ms;
  std::size_t i = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const glm::dvec3 p =
        humerusModel().mesh.positionsMm[(i++ * 7919) % humerusModel().mesh.vertexCount()];
    for (int k = 0; k < 60; ++k) scene.drill->removeInSphere(p, 1.46, 1);
    state.ResumeTiming();
    const Clock::time_point t0 = Clock::now();
    scene.updateSurface();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  report(state, ms, "");
}
BENCHMARK(BM_IncrementalSphereRemoved)
    ->Arg(250)
    ->ArgName("voxel_um")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(200);

// The seed's Tables 1 and 2: voxels, triangles, vertices and the mesh time, broken down.
void BM_SeedTables(benchmark::State& state, const std::string& which) {
  static const TriangleMesh shared = [] {
    const std::string path =
        std::string(OSTEON_SHARED_DATA_DIR) + "/humerus_R_opensim_myosuite.stl";
    osteon::simulation::BoneSource source;  // in metres
    source.input = path;
    source.units = "m";
    return std::filesystem::exists(path) ? osteon::simulation::loadBoneMesh(source).mesh
                                         : TriangleMesh{};
  }();
  const TriangleMesh& mesh = which == "humerus_shared" ? shared : humerusModel().mesh;
  if (mesh.triangles.empty()) {
    state.SkipWithError("shared data not found");
    return;
  }
  VoxelizeOptions options;
  options.voxelSizeMm = double(state.range(0)) / 1000.0;
  const VoxelGrid grid = voxelize(mesh, options);
  SurfaceTimings sum;
  SurfaceMesh m;
  int runs = 0;
  for (auto _ : state) {
    SurfaceTimings t;
    m = extractSurface(grid, SurfaceOptions{}, &t);
    sum.extractMs += t.extractMs;
    sum.smoothMs += t.smoothMs;
    sum.normalsMs += t.normalsMs;
    sum.otherMs += t.otherMs;
    sum.totalMs += t.totalMs;
    ++runs;
  }
  state.counters["voxels_inside"] = double(grid.countVoxels(kFillHalf));
  state.counters["triangles"] = double(m.triangleCount());
  state.counters["vertices"] = double(m.vertexCount());
  state.counters["extract_ms"] = sum.extractMs / runs;
  state.counters["smooth_ms"] = sum.smoothMs / runs;
  state.counters["normals_ms"] = sum.normalsMs / runs;
  state.counters["other_ms"] = sum.otherMs / runs;
  state.counters["total_ms"] = sum.totalMs / runs;
}

}  // namespace

void registerTables() {
  for (const char* which : {"humerus_default", "humerus_shared"}) {
    const std::string w = which;
    benchmark::RegisterBenchmark(("seed_table/" + w).c_str(),
                                 [w](benchmark::State& s) { BM_SeedTables(s, w); })
        ->Arg(1200)
        ->Arg(900)
        ->Arg(720)
        ->Arg(540)
        ->ArgName("voxel_um")
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace osteon::bench
