// The memory estimate for a volume (volumeLoadMemoryBytes, what loadVolume refuses up front)
// against what loading really takes: the growth of the peak resident set while a gzip volume of
// each kind loads (a label map with every brick allocated, a noisy CT, a double volume whose
// axes are reordered and flipped) stays within the estimate's per-voxel part.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <malloc.h>
#include <random>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"
#include "support/shapes.h"
#include "support/volume_files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;
using test::TestVolume;

// A field of /proc/self/status in bytes ("VmRSS", "VmHWM"), -1 if unknown.
double statusBytes(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field + ":", 0) == 0) return std::stod(line.substr(field.size() + 1)) * 1024.0;
  }
  return -1.0;
}

// Resets the peak resident set to the present one (Linux 4.0+); false where it cannot.
bool resetPeak() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.flush();
  return bool(clear);
}

class VolumeMemory : public ::testing::Test {
 protected:
  void SetUp() override {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    // Their shadow memory and quarantine are part of every peak: the Release build measures.
    GTEST_SKIP() << "a sanitizer's allocator says nothing of a load's memory";
#endif
  }
  std::string dir_ = test::makeTempDir("volume_memory");
  void TearDown() override {
    fs::remove_all(dir_);
  }
  std::string file(const std::string& name) const {
    return dir_ + "/" + name;
  }

  // The growth of the peak resident set while `name` loads; with exactMalloc, in a child process
  // whose allocator returns every large buffer when freed (a fixed mmap threshold), so the
  // growth is the live bytes. Checks the grid's inside voxels too.
  double peakGrowth(const std::string& name, std::uint64_t expectedInside, bool exactMalloc) {
    int fd[2];
    if (exactMalloc && pipe(fd) != 0) return -1.0;
    const pid_t pid = exactMalloc ? fork() : 0;
    if (pid < 0) return -1.0;
    if (exactMalloc && pid > 0) {
      close(fd[1]);
      double growth = -1.0;
      if (read(fd[0], &growth, sizeof growth) != ssize_t(sizeof growth)) growth = -1.0;
      close(fd[0]);
      int status = 0;
      waitpid(pid, &status, 0);
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
          << "the child found other inside voxels";
      return growth;
    }
    if (exactMalloc) mallopt(M_MMAP_THRESHOLD, 128 * 1024);
    malloc_trim(0);  // freed memory of earlier tests goes back, so reusing it counts as growth
    const bool reset = resetPeak();
    const double before = statusBytes("VmRSS");
    std::uint64_t inside = 0;
    {
      const VolumeLoad load = loadVolume(file(name));
      inside = load.grid.countVoxels(kFillHalf);
    }
    const double growth = reset && before > 0.0 ? statusBytes("VmHWM") - before : -1.0;
    if (exactMalloc) {
      if (write(fd[1], &growth, sizeof growth) != ssize_t(sizeof growth)) _exit(3);
      _exit(inside == expectedInside ? 0 : 1);
    }
    EXPECT_EQ(inside, expectedInside);
    return growth;
  }

  void expectWithinEstimate(const std::string& name, glm::ivec3 sizes, std::size_t scalarBytes,
                            std::uint64_t expectedInside) {
    SCOPED_TRACE(name);
    // What the volume may add to a running osteon, and the part of it that grows with voxels.
    const double allowed = volumeLoadMemoryBytes(sizes, scalarBytes) - kVolumeLoadProcessBytes;
    const double perVoxelPart = allowed - kVolumeLoadHeapSlackBytes;
    const double voxels = double(sizes.x) * sizes.y * sizes.z;
    const double exact = peakGrowth(name, expectedInside, true);
    const double asRun = peakGrowth(name, expectedInside, false);
    if (exact < 0.0 || asRun < 0.0)
      GTEST_SKIP() << "/proc/self/clear_refs cannot reset the peak resident set here";
    RecordProperty(name + "_bytes_per_voxel_measured", std::to_string(exact / voxels));
    RecordProperty(name + "_bytes_per_voxel_estimated", std::to_string(perVoxelPart / voxels));
    std::printf("%s: %.2f bytes a voxel live at the peak (%.2f as allocated), %.2f estimated\n",
                name.c_str(), exact / voxels, asRun / voxels, perVoxelPart / voxels);
    // 8 MB for the code a forked child faults in afresh (osteon's own, in kVolumeLoadProcessBytes).
    EXPECT_LE(exact, perVoxelPart + 8e6)
        << exact / voxels << " bytes a voxel, " << perVoxelPart / voxels << " estimated";
    EXPECT_LE(asRun, allowed) << asRun / voxels << " bytes a voxel, " << allowed / voxels
                              << " allowed";
    // And the estimate is not a blanket: loading does use most of it (a CT needs no distance).
    EXPECT_GE(exact, 0.6 * perVoxelPart)
        << exact / voxels << " bytes a voxel, " << perVoxelPart / voxels << " estimated";
  }
};

TEST_F(VolumeMemory, ALabelMapWithEveryBrickAllocatedStaysWithinTheEstimate) {
  // Random labels 0 and 1: no brick is uniform, every one is allocated.
  TestVolume v;
  v.sizes = {256, 256, 128};
  std::mt19937 rng(30);
  std::uint64_t ones = 0;
  v.values.resize(std::size_t(v.sizes.x) * std::size_t(v.sizes.y) * std::size_t(v.sizes.z));
  for (double& x : v.values) {
    x = double(rng() & 1u);
    ones += x > 0.0;
  }
  test::writeTestNrrd(file("labels.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values),
                      true);
  expectWithinEstimate("labels.nrrd", v.sizes, 1, ones);
}

TEST_F(VolumeMemory, ANoisyCtStaysWithinTheEstimate) {
  TestVolume v;
  v.sizes = {160, 160, 128};
  std::mt19937 rng(31);
  std::normal_distribution<double> noise(0.0, 30.0);
  std::uint64_t bone = 0;
  v.values.resize(std::size_t(v.sizes.x) * std::size_t(v.sizes.y) * std::size_t(v.sizes.z));
  for (std::size_t i = 0; i < v.values.size(); ++i) {
    const bool in = (rng() & 1u) != 0;  // bone and air at random: no brick is uniform
    v.values[i] = std::round((in ? 1200.0 : -900.0) + noise(rng));
    bone += v.values[i] >= kDefaultIsoHu;
  }
  test::writeTestNifti(file("ct.nii.gz"), v, 4, 16, test::encodeAs<std::int16_t>(v.values), true);
  expectWithinEstimate("ct.nii.gz", v.sizes, 2, bone);
}

TEST_F(VolumeMemory, ADoubleVolumeWhoseAxesAreReorderedStaysWithinTheEstimate) {
  // Stored axes along -P, L, S: the values are copied into LPS order while loading.
  TestVolume v;
  v.sizes = {128, 128, 96};
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> hu(-1000.0, 1500.0);
  std::uint64_t bone = 0;
  v.values.resize(std::size_t(v.sizes.x) * std::size_t(v.sizes.y) * std::size_t(v.sizes.z));
  for (double& x : v.values) {
    x = std::round(hu(rng));  // whole HU: inside exactly at or above the iso level
    bone += x >= kDefaultIsoHu;
  }
  test::writeTestNrrd(file("d.nrrd"), v, "double", test::encodeAs<double>(v.values), true, "",
                      "(0,-1,0) (1,0,0) (0,0,1)");
  expectWithinEstimate("d.nrrd", v.sizes, 8, bone);
}

}  // namespace
}  // namespace osteon::geometry
