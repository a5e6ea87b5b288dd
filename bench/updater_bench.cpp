// The incremental updater's first full extraction against extractSurface on the same grid
// (two smoothing passes and normals, both threads), interleaved run by run, and what each holds
// in memory afterwards: the updater's structures against the mesh extractSurface returns.
//   osteon_bench_updater [RUNS] [VOXEL_SIZES...]   e.g. osteon_bench_updater 5 0.54 0.3
// Bones: the built-in humerus, and the shared humerus and femur (metres) when present
// (OSTEON_SHARED_DATA_DIR). A plain program: medians and ranges, one table row per case.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "osteon/core/timing.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/simulation/session.h"

namespace {

using namespace osteon;

struct Bone {
  std::string name, argument;
  double scaleToMm;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::size_t meshBytes(const geometry::SurfaceMesh& m) {
  return m.positionsMm.capacity() * sizeof(glm::dvec3) + m.normals.capacity() * sizeof(glm::dvec3) +
         m.triangles.capacity() * sizeof(glm::u32vec3) +
         m.brickRanges.capacity() * sizeof(geometry::SurfaceMesh::BrickRange);
}

void runCase(const Bone& bone, double voxelSizeMm, int runs) {
  const auto model =
      simulation::BoneModel::open(bone.argument, bone.scaleToMm, voxelSizeMm, {}, false);
  const geometry::VoxelGrid& grid = model->grid();
  const geometry::SurfaceOptions options;
  std::vector<double> extractMs, updaterMs, ratio;
  std::size_t triangles = 0, updaterBytes = 0, surfaceBytes = 0;
  geometry::SurfaceUpdater::Memory parts;
  for (int r = 0; r < runs; ++r) {
    // Alternate which goes first, so neither always finds the caches warmed by the other.
    for (int k = 0; k < 2; ++k) {
      if ((k + r) % 2 == 0) {
        const Clock::time_point start = Clock::now();
        const geometry::SurfaceMesh m = geometry::extractSurface(grid, options);
        extractMs.push_back(msSince(start));
        triangles = m.triangleCount();
        surfaceBytes = meshBytes(m);
      } else {
        const Clock::time_point start = Clock::now();
        const geometry::SurfaceUpdater u(grid, options);
        updaterMs.push_back(msSince(start));
        parts = u.memory();
        updaterBytes = parts.total();
      }
    }
    ratio.push_back(updaterMs.back() / extractMs.back());
  }
  const double voxels = double(grid.countVoxels(1));
  std::printf(
      "| %s | %.2f | %.0f | %zu | %.1f (%.1f-%.1f) | %.1f (%.1f-%.1f) | %.2f | %.1f | %.1f | "
      "%.1f | %.1f / %.1f / %.1f / %.1f / %.1f |\n",
      bone.name.c_str(), voxelSizeMm, voxels, triangles, median(extractMs),
      *std::min_element(extractMs.begin(), extractMs.end()),
      *std::max_element(extractMs.begin(), extractMs.end()), median(updaterMs),
      *std::min_element(updaterMs.begin(), updaterMs.end()),
      *std::max_element(updaterMs.begin(), updaterMs.end()), median(ratio),
      double(surfaceBytes) / 1e6, double(updaterBytes) / 1e6, double(updaterBytes) / voxels,
      double(parts.cellBricks) / 1e6, double(parts.triangles) / 1e6, double(parts.vertices) / 1e6,
      double(parts.loops) / 1e6, double(parts.tables) / 1e6);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  std::vector<double> sizes;
  for (int i = 2; i < argc; ++i) sizes.push_back(std::atof(argv[i]));
  if (sizes.empty()) sizes = {0.54, 0.3};
  const std::string data = std::getenv("OSTEON_SHARED_DATA_DIR")
                               ? std::getenv("OSTEON_SHARED_DATA_DIR")
                               : OSTEON_SHARED_DATA_DIR;
  std::vector<Bone> bones = {{"humerus (built-in)", "default", 1.0}};
  for (const auto& [name, file] :
       {std::pair<const char*, const char*>{"humerus (OpenSim)", "humerus_R_opensim_myosuite.stl"},
        {"femur (OpenSim)", "femur_R_opensim_myosuite.stl"}}) {
    if (std::filesystem::exists(data + "/" + file))
      bones.push_back({name, data + "/" + file, 1000.0});
  }
  std::printf(
      "| bone | voxel mm | voxels with bone | triangles | extractSurface ms | updater first "
      "extraction ms | updater / extract (median of runs) | mesh MB | updater MB | updater B per "
      "voxel | cell bricks / triangles / vertices / loops / tables MB |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  for (const Bone& bone : bones)
    for (const double vs : sizes) runCase(bone, vs, runs);
  return 0;
}
