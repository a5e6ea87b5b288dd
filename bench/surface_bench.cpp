// Surface extraction (seed 3.4): full extraction against VTK's vtkFlyingEdges3D on the same
// uint8 volumes, the incremental update after one drilling step at 0.25 mm, and the seed's
// Tables 1 and 2 for the built-in and the shared humerus. Figures go to docs/performance.md.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/hierarchy/refinement.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/removal.h"

#ifdef OSTEON_HAVE_VTK
#include <vtkSMPTools.h>

#include "flying_edges.h"
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

namespace {

using namespace osteon::geometry;
using osteon::bench::Clock;

const VoxelGrid& volume(const std::string& name, int n) {
  return osteon::bench::benchVolume(name, n);
}

// Minor page faults of this thread so far.
long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

void BM_ExtractOsteon(benchmark::State& state, const std::string& name, bool singleThread) {
  const VoxelGrid& g = volume(name, int(state.range(0)));
  std::unique_ptr<tbb::global_control> oneThread;
  if (singleThread) {
    oneThread =
        std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
  }
  SurfaceOptions options;  // marching cubes only: no smoothing, no normals, like FlyingEdges
  options.smoothIterations = 0;
  options.computeNormals = false;
  std::size_t triangles = 0;
  const long faults = minorFaults();
  for (auto _ : state) {
    const SurfaceMesh m = extractSurface(g, options);
    triangles = m.triangleCount();
    benchmark::DoNotOptimize(triangles);
  }
  // Page faults per extraction: fresh output pages the kernel maps and zeroes.
  state.counters["faults"] =
      benchmark::Counter(double(minorFaults() - faults), benchmark::Counter::kAvgIterations);
  state.counters["triangles"] = double(triangles);
  state.counters["voxels"] = double(g.voxelCount());
}

// Writes 64 MiB (untimed), which evicts everything an extraction used from every cache level.
void evictCaches(benchmark::State& state) {
  static std::vector<char> sweep(std::size_t(64) << 20);
  state.PauseTiming();
  for (std::size_t i = 0; i < sweep.size(); i += 64) sweep[i] = char(sweep[i] + 1);
  benchmark::DoNotOptimize(sweep.data());
  state.ResumeTiming();
}

// osteon with every cache cold (evictCaches before each extraction): what a caller sees when
// extraction is occasional, or shares the machine.
void BM_ExtractOsteonCold(benchmark::State& state, const std::string& name) {
  const VoxelGrid& g = volume(name, int(state.range(0)));
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  SurfaceOptions options;
  options.smoothIterations = 0;
  options.computeNormals = false;
  for (auto _ : state) {
    evictCaches(state);
    const SurfaceMesh m = extractSurface(g, options);
    benchmark::DoNotOptimize(m.triangles.data());
  }
}

#ifdef OSTEON_HAVE_VTK
using osteon::bench::flyingEdges;
using osteon::bench::imageOf;

void BM_ExtractFlyingEdges(benchmark::State& state, const std::string& name) {
  const VoxelGrid& g = volume(name, int(state.range(0)));
  const vtkSmartPointer<vtkImageData> image = imageOf(g);
  vtkSMPTools::Initialize(1);  // single thread, as the peer is quoted
  std::size_t triangles = 0;
  const long faults = minorFaults();
  for (auto _ : state) {
    triangles = flyingEdges(image);
    benchmark::DoNotOptimize(triangles);
  }
  state.counters["faults"] =
      benchmark::Counter(double(minorFaults() - faults), benchmark::Counter::kAvgIterations);
  state.counters["triangles"] = double(triangles);
  state.counters["voxels"] = double(g.voxelCount());
}

// FlyingEdges with every cache cold, as BM_ExtractOsteonCold.
void BM_ExtractFlyingEdgesCold(benchmark::State& state, const std::string& name) {
  const VoxelGrid& g = volume(name, int(state.range(0)));
  const vtkSmartPointer<vtkImageData> image = imageOf(g);
  vtkSMPTools::Initialize(1);
  for (auto _ : state) {
    evictCaches(state);
    benchmark::DoNotOptimize(flyingEdges(image));
  }
}

// osteon and FlyingEdges alternately, one extraction each per iteration, single-threaded: on a
// shared machine whose speed drifts from minute to minute the two see the same drift, so the
// median of the per-iteration ratios is steadier than a ratio of two separate runs. cold:
// every cache evicted (untimed) before each extraction, both sides.
void BM_ExtractSideBySide(benchmark::State& state, const std::string& name, bool cold) {
  const VoxelGrid& g = volume(name, int(state.range(0)));
  const vtkSmartPointer<vtkImageData> image = imageOf(g);
  vtkSMPTools::Initialize(1);
  tbb::global_control oneThread(tbb::global_control::max_allowed_parallelism, 1);
  SurfaceOptions options;
  options.smoothIterations = 0;
  options.computeNormals = false;
  std::vector<double> osteonMs, peerMs, ratio;
  long osteonFaults = 0, peerFaults = 0;
  for (auto _ : state) {
    if (cold) evictCaches(state);
    long faults = minorFaults();
    Clock::time_point t0 = Clock::now();
    const SurfaceMesh m = extractSurface(g, options);
    benchmark::DoNotOptimize(m.triangles.data());
    const double ours = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    osteonFaults += minorFaults() - faults;
    if (cold) evictCaches(state);
    faults = minorFaults();
    t0 = Clock::now();
    benchmark::DoNotOptimize(flyingEdges(image));
    const double peer = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    peerFaults += minorFaults() - faults;
    osteonMs.push_back(ours);
    peerMs.push_back(peer);
    ratio.push_back(peer / ours);
  }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
  };
  state.counters["osteon_ms"] = median(osteonMs);
  state.counters["flyingedges_ms"] = median(peerMs);
  state.counters["fe_over_osteon"] = median(ratio);
  // Page faults per extraction (fresh output pages the kernel zeroes), each side's own.
  const double calls = double(std::max<std::size_t>(osteonMs.size(), 1));
  state.counters["osteon_faults"] = double(osteonFaults) / calls;
  state.counters["flyingedges_faults"] = double(peerFaults) / calls;
}
#endif

// A benchmark registered for 64^3, 128^3 and 256^3 volumes, in milliseconds of wall-clock time.
template <typename Fn>
benchmark::internal::Benchmark* atEachSize(const std::string& name, Fn&& fn) {
  return benchmark::RegisterBenchmark(name.c_str(), std::forward<Fn>(fn))
      ->Arg(64)
      ->Arg(128)
      ->Arg(256)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

void registerExtraction() {
  for (const char* name : {"sphere_drilled", "humerus"}) {
    const std::string n = name;
    atEachSize("extract/osteon_2threads/" + n,
               [n](benchmark::State& s) { BM_ExtractOsteon(s, n, false); });
    atEachSize("extract/osteon_1thread/" + n,
               [n](benchmark::State& s) { BM_ExtractOsteon(s, n, true); });
    atEachSize("extract/osteon_1thread_cold/" + n,
               [n](benchmark::State& s) { BM_ExtractOsteonCold(s, n); });
#ifdef OSTEON_HAVE_VTK
    atEachSize("extract/vtkFlyingEdges3D_1thread/" + n,
               [n](benchmark::State& s) { BM_ExtractFlyingEdges(s, n); });
    atEachSize("extract/vtkFlyingEdges3D_1thread_cold/" + n,
               [n](benchmark::State& s) { BM_ExtractFlyingEdgesCold(s, n); });
    atEachSize("extract/side_by_side_1thread/" + n, [n](benchmark::State& s) {
      BM_ExtractSideBySide(s, n, false);
    })->MinTime(2.0);
    atEachSize("extract/side_by_side_1thread_cold/" + n, [n](benchmark::State& s) {
      BM_ExtractSideBySide(s, n, true);
    })->MinTime(2.0);
#endif
  }
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // glibc gives freed memory back to the kernel as its dynamic thresholds see fit, so an
  // extractor could take fresh pages for its output on every call, or not, by the heap's
  // layout (FlyingEdges at 128^3: 8.8 or 22 ms warm in two builds of this benchmark). Kept
  // off: every extractor runs with its memory reused, as in a long-lived process.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  registerExtraction();
  osteon::bench::registerTables();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
