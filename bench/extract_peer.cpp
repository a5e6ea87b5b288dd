// The per-process side of the extraction comparison (extract_interleaved.sh): writes the
// benchmark's volumes as osteon grids, so `osteon mesh` reads the same voxels, and runs VTK's
// vtkFlyingEdges3D once on such a grid, on one thread, as `osteon mesh` runs its extraction
// once in a fresh process: fresh output pages, caches holding what loading left there. And,
// to see what a fresh process costs, osteon's extraction repeated in one process.
#include <cstdio>
#include <exception>
#include <string>
#include <sys/resource.h>
#include <vtkSMPTools.h>

#include "bench_volumes.h"
#include "flying_edges.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/surface/surface.h"

namespace {

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

int usage() {
  std::fprintf(stderr,
               "usage: osteon_bench_extract_peer write DIR\n"
               "       osteon_bench_extract_peer flyingedges GRID.nrrd\n"
               "       osteon_bench_extract_peer osteon GRID.nrrd [REPEATS]\n");
  return 2;
}

// DIR/sphere_N.nrrd and DIR/humerus_N.nrrd (fill and density) for N = 64, 128, 256.
int writeVolumes(const std::string& dir) {
  for (const char* name : {"sphere", "humerus"})
    for (int n : {64, 128, 256}) {
      const std::string path = dir + "/" + name + "_" + std::to_string(n) + ".nrrd";
      osteon::geometry::writeNrrd(osteon::bench::benchVolume(name, n), path);
      std::printf("%s\n", path.c_str());
    }
  return 0;
}

// One FlyingEdges extraction of the grid, timed as osteon mesh times its own (the extraction
// alone, not the loading or the conversion to VTK's image): one JSON line.
int flyingEdgesOnce(const std::string& path) {
  const osteon::geometry::NrrdReadResult read = osteon::geometry::readNrrd(path);
  const vtkSmartPointer<vtkImageData> image = osteon::bench::imageOf(read.grid);
  vtkSMPTools::Initialize(1);
  const osteon::Clock::time_point start = osteon::Clock::now();
  const long faults = minorFaults();
  const std::size_t triangles = osteon::bench::flyingEdges(image);
  const double ms = osteon::msSince(start);
  std::printf("{\"extract_ms\": %.4f, \"triangles\": %zu, \"faults\": %ld}\n", ms, triangles,
              minorFaults() - faults);
  return 0;
}

// osteon's extraction (marching cubes only, as FlyingEdges) repeated in one process on the
// grid as loaded: the first call against the later ones, with the page faults of each.
int osteonRepeated(const std::string& path, int repeats) {
  const osteon::geometry::NrrdReadResult read = osteon::geometry::readNrrd(path);
  osteon::geometry::SurfaceOptions options;
  options.smoothIterations = 0;
  options.computeNormals = false;
  for (int i = 0; i < repeats; ++i) {
    const long faults = minorFaults();
    const osteon::Clock::time_point start = osteon::Clock::now();
    const osteon::geometry::SurfaceMesh m = osteon::geometry::extractSurface(read.grid, options);
    const double ms = osteon::msSince(start);
    std::printf(
        "{\"extract_ms\": %.4f, \"triangles\": %zu, \"vertices\": %zu, \"faults\": %ld, "
        "\"stored_bricks\": %zu}\n",
        ms, m.triangleCount(), m.vertexCount(), minorFaults() - faults,
        read.grid.allocatedBrickCount());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) return usage();
  const std::string mode = argv[1];
  try {
    if (mode == "write") return writeVolumes(argv[2]);
    if (mode == "flyingedges") return flyingEdgesOnce(argv[2]);
    if (mode == "osteon") return osteonRepeated(argv[2], argc == 4 ? std::stoi(argv[3]) : 1);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "osteon_bench_extract_peer: error: %s\n", e.what());
    return 2;
  }
  return usage();
}
