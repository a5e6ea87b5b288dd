// Dynamic Proximity Hierarchy (seed 3.3) and refinement (seed 3.5) on the built-in humerus:
// build time against voxel count, sphere-query latency and refinement create/expire latency
// as p50/p99 in microseconds (the 1 kHz haptic step has 1000 us for everything).
#include <algorithm>
#include <chrono>
#include <map>
#include <random>

#include <benchmark/benchmark.h>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/geometry/voxels/voxelizer.h"

namespace {

using namespace osteon::geometry;
using Clock = std::chrono::steady_clock;

constexpr double kDrillRadiusMm = 1.46;  // seed: 2.92 mm drill tip

const HumerusModel& model() {
  static const HumerusModel m = buildHumerusModel();
  return m;
}

const VoxelGrid& gridAt(double voxelSizeMm) {
  static std::map<double, VoxelGrid> cache;
  auto it = cache.find(voxelSizeMm);
  if (it == cache.end()) {
    VoxelizeOptions options;
    options.voxelSizeMm = voxelSizeMm;
    it = cache.emplace(voxelSizeMm, voxelize(model().mesh, options)).first;
  }
  return it->second;
}

// Tool centres on the bone surface: mesh vertices, fixed seed.
std::vector<glm::dvec3> surfacePoints(std::size_t count) {
  std::mt19937 rng(2026);
  std::uniform_int_distribution<std::size_t> pick(0, model().mesh.vertexCount() - 1);
  std::vector<glm::dvec3> points(count);
  for (glm::dvec3& p : points) p = model().mesh.positionsMm[pick(rng)];
  return points;
}

void report(benchmark::State& state, std::vector<double>& us, const char* prefix) {
  std::sort(us.begin(), us.end());
  const auto at = [&](double q) {
    return us[std::min(us.size() - 1, std::size_t(q * double(us.size())))];
  };
  state.counters[std::string(prefix) + "p50_us"] = at(0.50);
  state.counters[std::string(prefix) + "p99_us"] = at(0.99);
  state.counters[std::string(prefix) + "max_us"] = us.back();
}

void BM_DphBuild(benchmark::State& state) {
  const VoxelGrid& grid = gridAt(double(state.range(0)) / 1000.0);
  std::size_t levels = 0, voxels = 0, bytes = 0;
  for (auto _ : state) {
    const auto h = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
    levels = std::size_t(h.levelCount());
    voxels = h.voxelCount();
    bytes = h.memoryBytes();
    benchmark::DoNotOptimize(levels);
  }
  state.counters["voxels"] = double(voxels);
  state.counters["levels"] = double(levels);
  state.counters["MB"] = double(bytes) / 1e6;
  state.counters["ns_per_voxel"] = benchmark::Counter(
      double(voxels), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_DphBuild)
    ->Arg(1200)
    ->Arg(540)
    ->Arg(300)
    ->Arg(270)
    ->Arg(250)
    ->ArgName("voxel_um")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MeasureProcessCPUTime();

// The collision query of one haptic step: voxels between the drill's layers are within the
// outer sphere (inner radius + two finest voxels).
void BM_DphSphereQuery(benchmark::State& state) {
  const VoxelGrid& grid = gridAt(double(state.range(0)) / 1000.0);
  const auto h = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  const std::vector<glm::dvec3> points = surfacePoints(4096);
  const double outer = kDrillRadiusMm + 2.0 * grid.voxelSizeMm();
  DphQueryScratch scratch;
  std::vector<double> us;
  us.reserve(1 << 20);
  std::size_t found = 0, i = 0;
  for (auto _ : state) {
    const glm::dvec3& p = points[i++ % points.size()];
    const Clock::time_point t0 = Clock::now();
    h.forEachVoxelInSphere(p, outer, scratch, [&](const glm::ivec3&) { ++found; });
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  benchmark::DoNotOptimize(found);
  state.counters["voxels_per_query"] = double(found) / double(us.size());
  report(state, us, "");
}
BENCHMARK(BM_DphSphereQuery)
    ->Arg(1200)
    ->Arg(540)
    ->Arg(250)
    ->ArgName("voxel_um")
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(20000);

// Refining the voxels under the drill tip at 1.2 mm to level -2, then expiring them.
void BM_RefineCreateExpire(benchmark::State& state) {
  VoxelGrid grid = gridAt(1.2);
  auto h = DynamicProximityHierarchy::build(grid, DphBuildOptions{});
  const EmbreeScene scene(model().mesh);
  const FineFillSource source = FineFillSource::sample(grid, model().mesh, scene);
  RefinementOptions options;
  options.depth = int(state.range(0));
  RefinedVoxels refined(grid, h, &source, options);
  const std::vector<glm::dvec3> points = surfacePoints(4096);
  const double outer = kDrillRadiusMm + 2.0 * refined.sampleSizeMm();
  std::vector<double> create, expire;
  create.reserve(1 << 16);
  expire.reserve(1 << 16);
  std::size_t cells = 0, i = 0;
  double now = 0.0;
  for (auto _ : state) {
    const glm::dvec3& p = points[i++ % points.size()];
    const Clock::time_point t0 = Clock::now();
    cells += std::size_t(refined.refineAround(p, outer, now));
    const Clock::time_point t1 = Clock::now();
    now += 10.0;  // the tool has gone: everything is past its timeout
    refined.expire(now);
    const Clock::time_point t2 = Clock::now();
    create.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    expire.push_back(std::chrono::duration<double, std::micro>(t2 - t1).count());
  }
  state.counters["voxels_refined"] = double(cells) / double(create.size());
  report(state, create, "create_");
  report(state, expire, "expire_");
}
BENCHMARK(BM_RefineCreateExpire)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("levels")
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(20000);

}  // namespace

BENCHMARK_MAIN();
