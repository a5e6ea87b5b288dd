// Loading and meshing a clinical-size CT (512 x 512 x 350 at 0.7 mm, int16 and float): the
// volume is written slice by slice to a temporary folder, then opened and meshed as
// `osteon mesh CT.nrrd` does (BoneModel::open, extractSurface), timed, with the process's peak
// resident memory over that span (VmHWM, reset through /proc/self/clear_refs) set against the
// volume's raw size. A plain program; figures go into docs/performance.md.
//   osteon_bench_volume                     the isotropic int16 and float CTs, a table
//   osteon_bench_volume write KIND FILE     a bone phantom CT (ct_phantom.h): KIND aniso, thick,
//                                           oblique, iso or labels
//   osteon_bench_volume measure FILE JSON   load and mesh FILE once, the figures to JSON
// (bench/volume_resample_bench.sh runs builds interleaved on the phantoms.)
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/resource.h>
#include <unistd.h>
#include <vector>

#include "ct_phantom.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/simulation/bone_source.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kNx = 512, kNy = 512, kNz = 350;
constexpr double kVoxelMm = 0.7;

// HU at a voxel centre: air with noise, a body of soft tissue, two long bones (cortical shell
// around marrow) and a round bone head at one end.
double hounsfield(int x, int y, int z, std::uint32_t& seed) {
  seed = seed * 1664525u + 1013904223u;
  const double noise = double(seed >> 24) / 255.0 * 40.0 - 20.0;
  const double px = (x - kNx / 2) * kVoxelMm, py = (y - kNy / 2) * kVoxelMm, pz = z * kVoxelMm;
  const double body = (px / 150.0) * (px / 150.0) + (py / 110.0) * (py / 110.0);
  if (body > 1.0) return -1000.0 + noise;
  double hu = 40.0 + noise;
  for (const double cx : {-60.0, 60.0}) {
    const double r = std::hypot(px - cx, py);
    const double head = std::sqrt((px - cx) * (px - cx) + py * py + (pz - 200.0) * (pz - 200.0));
    if (r < 14.0 && pz < 200.0) hu = r > 9.0 ? 1400.0 + noise : 200.0 + noise;
    if (head < 24.0) hu = head > 21.0 ? 1100.0 + noise : 350.0 + noise;
  }
  return hu;
}

template <typename T>
std::string writeCt(const std::string& dir, const char* nrrdType) {
  const std::string path = dir + "/ct_" + nrrdType + ".nrrd";
  std::ofstream out(path, std::ios::binary);
  out << "NRRD0004\ntype: " << nrrdType << "\ndimension: 3\nspace: left-posterior-superior\n"
      << "sizes: " << kNx << " " << kNy << " " << kNz << "\nspace directions: (" << kVoxelMm
      << ",0,0) (0," << kVoxelMm << ",0) (0,0," << kVoxelMm << ")\nkinds: domain domain domain\n"
      << "endian: little\nencoding: raw\nspace origin: (0,0,0)\n\n";
  std::vector<T> slice(std::size_t(kNx) * kNy);
  std::uint32_t seed = 1;
  for (int z = 0; z < kNz; ++z) {
    for (int y = 0; y < kNy; ++y) {
      for (int x = 0; x < kNx; ++x)
        slice[std::size_t(y) * kNx + std::size_t(x)] = T(hounsfield(x, y, z, seed));
    }
    out.write(reinterpret_cast<const char*>(slice.data()),
              std::streamsize(slice.size() * sizeof(T)));
  }
  return path;
}

double peakResidentMb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return -1.0;
}

void resetPeakResident() {
  std::ofstream("/proc/self/clear_refs") << "5";
}

// User and system time of the process so far (ms): the machine may be shared, wall time not ours.
double cpuMs() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e6 + double(u.ru_utime.tv_usec) +
          double(u.ru_stime.tv_usec)) /
         1e3;
}

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Measured {
  double loadMs, meshMs, cpuMs, peakMb;
  std::size_t triangles;
};

// FILE opened and meshed once, as `osteon mesh FILE` does.
Measured measure(const std::string& path) {
  osteon::simulation::BoneSource source;
  source.input = path;
  source.forSession = false;
  source.sampleFineFills = false;
  resetPeakResident();
  const double cpuStart = cpuMs();
  const Clock::time_point start = Clock::now();
  osteon::simulation::OpenedBone opened = osteon::simulation::BoneModel::open(source);
  const double loadMs = msSince(start);
  const osteon::geometry::SurfaceMesh surface =
      osteon::geometry::extractSurface(opened.bone->grid(), {});
  const double totalMs = msSince(start);
  return {loadMs, totalMs - loadMs, cpuMs() - cpuStart, peakResidentMb(), surface.triangleCount()};
}

template <typename T>
void run(const std::string& dir, const char* nrrdType) {
  const std::string path = writeCt<T>(dir, nrrdType);
  const double rawMb = double(kNx) * kNy * kNz * sizeof(T) / (1024.0 * 1024.0);
  const Measured m = measure(path);
  std::printf("| %s | %.0f MB | %.0f ms | %.0f ms | %.0f ms | %.0f ms | %.0f MB | %.2f | %zu |\n",
              nrrdType, rawMb, m.loadMs, m.meshMs, m.loadMs + m.meshMs, m.cpuMs, m.peakMb,
              m.peakMb / rawMb, m.triangles);
  fs::remove(path);
}

// One file measured, its figures as one JSON object (the raw size is the file's values).
int measureToJson(const std::string& path, const std::string& json) {
  const double rawMb = double(fs::file_size(path)) / (1024.0 * 1024.0);
  const Measured m = measure(path);
  std::ofstream out(json);
  out << "{\"load_ms\": " << m.loadMs << ", \"mesh_ms\": " << m.meshMs
      << ", \"total_ms\": " << m.loadMs + m.meshMs << ", \"cpu_ms\": " << m.cpuMs
      << ", \"peak_mb\": " << m.peakMb << ", \"raw_mb\": " << rawMb
      << ", \"triangles\": " << m.triangles << "}\n";
  return out ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 3 && args[0] == "write") {
    if (osteon::bench::writeCtPhantom(args[1], args[2])) return 0;
    std::fprintf(stderr, "osteon_bench_volume: unknown phantom %s\n", args[1].c_str());
    return 2;
  }
  if (args.size() == 3 && args[0] == "measure") return measureToJson(args[1], args[2]);
  if (!args.empty()) {
    std::fprintf(
        stderr,
        "usage: osteon_bench_volume [write iso|aniso|thick|oblique|labels FILE | measure FILE "
        "JSON]\n");
    return 2;
  }
  const std::string dir =
      (fs::temp_directory_path() / ("osteon_volume_bench_" + std::to_string(::getpid()))).string();
  fs::create_directories(dir);
  std::printf(
      "| CT | raw size | load | mesh | load + mesh | CPU time | peak RSS | peak / raw | "
      "triangles |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  run<std::int16_t>(dir, "int16");
  run<float>(dir, "float");
  fs::remove_all(dir);
  return 0;
}
