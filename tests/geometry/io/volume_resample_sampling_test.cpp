// A resampled CT and scalar volume, voxel by voxel, against a plain trilinear sample in doubles
// at each voxel's centre: the rows stepped in float and the bricks set whole from their
// footprints' value ranges give the same fills and densities.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"
#include "support/volume_files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

// Columns of an oblique 0.7 x 0.9 x 1.6 mm grid (written with few digits, so read back exactly).
const glm::dmat3 kIndexToLpsMm(0.68, 0.12, -0.1, -0.15, 0.86, 0.2, 0.25, -0.35, 1.5);
const char* const kDirections = "(0.68,0.12,-0.1) (-0.15,0.86,0.2) (0.25,-0.35,1.5)";

// A ball of cortex (1000-1500 HU) round marrow (at the 800 HU cortical threshold, and 450 HU
// deeper) in air, with noise: bricks wholly air, wholly bone, and straddling both thresholds.
test::TestVolume ballCt(std::uint32_t seed) {
  test::TestVolume v;
  v.sizes = {64, 60, 44};
  v.firstCentreMm = {-12.0, 5.0, 30.0};
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-20.0, 20.0);
  for (int z = 0; z < v.sizes.z; ++z) {
    for (int y = 0; y < v.sizes.y; ++y) {
      for (int x = 0; x < v.sizes.x; ++x) {
        const double r = glm::length(glm::dvec3(x - 32, y - 30, 1.9 * (z - 22)));
        const double hu = r > 28.0   ? -1000.0
                          : r > 19.0 ? 1250.0 + 8.0 * (x - 32)
                          : r > 9.0  ? 790.0
                                     : 450.0;
        v.values.push_back(std::round(hu + noise(random)));
      }
    }
  }
  return v;
}

// The stored values' trilinear value at an LPS point, `outside` past the grid by half a voxel.
double referenceSample(const test::TestVolume& v, glm::dvec3 pointMm, double outside) {
  glm::dvec3 q = glm::inverse(kIndexToLpsMm) * (pointMm - v.firstCentreMm);
  glm::ivec3 i0;
  glm::dvec3 t;
  for (int a = 0; a < 3; ++a) {
    if (!(q[a] >= -0.5 && q[a] <= v.sizes[a] - 0.5)) return outside;
    q[a] = std::clamp(q[a], 0.0, double(v.sizes[a] - 1));
    i0[a] = std::min(int(q[a]), v.sizes[a] - 2);
    t[a] = q[a] - i0[a];
  }
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 s = i0 + glm::ivec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const double w =
        ((c & 1) ? t.x : 1.0 - t.x) * ((c & 2) ? t.y : 1.0 - t.y) * ((c & 4) ? t.z : 1.0 - t.z);
    sum += w * v.values[std::size_t((s.z * v.sizes.y + s.y) * v.sizes.x + s.x)];
  }
  return sum;
}

double ramp(double value, double iso, double halfWidth) {
  return std::clamp((value - (iso - halfWidth)) / (2.0 * halfWidth), 0.0, 1.0) * kFillFull;
}

class VolumeResampleSampling : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("volume_resample_sampling");
  void TearDown() override { fs::remove_all(dir_); }
};

// Every voxel's fill within a rounding of the reference (2 of 16,320), and where `density` is
// given, its density the reference's away from the cortical threshold. Returns the voxels seen
// on each side of the ramp (0, ramped, full), so the test knows it met all three.
glm::ivec3 expectAsReference(const VoxelGrid& grid, const test::TestVolume& v, double outside,
                             const std::function<double(double)>& fillOf,
                             const std::function<int(double, double)>& density) {
  glm::ivec3 kinds(0);
  int wrong = 0;
  for (int z = 0; z < grid.dims().z; ++z) {
    for (int y = 0; y < grid.dims().y; ++y) {
      for (int x = 0; x < grid.dims().x; ++x) {
        const glm::dvec3 centre =
            grid.originMm() + (glm::dvec3(x, y, z) + 0.5) * grid.voxelSizeMm();
        const double value = referenceSample(v, centre, outside);
        const double fill = fillOf(value);
        ++kinds[fill <= 0.0 ? 0 : fill >= kFillFull ? 2 : 1];
        bool ok = std::abs(double(grid.fill({x, y, z})) - fill) <= 2.0;
        if (density && std::abs(value - kCorticalHu) > 0.01 && fill > 1.0)
          ok = ok && grid.density({x, y, z}) == density(value, fill);
        if (!ok && ++wrong <= 5) {
          ADD_FAILURE() << "voxel (" << x << ", " << y << ", " << z << "): value " << value
                        << ", fill " << grid.fill({x, y, z}) << " against " << fill << ", density "
                        << grid.density({x, y, z});
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0);
  return kinds;
}

TEST_F(VolumeResampleSampling, AResampledCtIsTheTrilinearSampleOfEveryVoxel) {
  for (const std::uint32_t seed : {1u, 2u}) {
    const test::TestVolume v = ballCt(seed);
    const std::string path = dir_ + "/ct.nrrd";
    test::writeTestNrrd(path, v, "short", test::encodeAs<std::int16_t>(v.values), false, "",
                        kDirections);
    const VolumeLoad load = loadVolume(path);
    ASSERT_EQ(load.kind, "ct");
    ASSERT_TRUE(load.transform.resampled);
    const glm::ivec3 kinds = expectAsReference(
        load.grid, v, load.minValue,
        [](double hu) { return ramp(hu, kDefaultIsoHu, kCtRampHalfWidthHu); },
        [](double hu, double) {
          return hu >= kCorticalHu ? kCtCorticalDensity : kCtCancellousDensity;
        });
    EXPECT_GT(kinds.x, 10000);
    EXPECT_GT(kinds.y, 300);
    EXPECT_GT(kinds.z, 10000);
  }
}

TEST_F(VolumeResampleSampling, AResampledScalarVolumeIsTheTrilinearSampleOfEveryVoxel) {
  test::TestVolume v = ballCt(3);
  // 0 to 220, more values than a label map's.
  for (std::size_t i = 0; i < v.values.size(); ++i)
    v.values[i] = std::round((v.values[i] + 1040.0) / 13.0) + double(i % 8);
  const auto [lo, hi] = std::minmax_element(v.values.begin(), v.values.end());
  const std::string path = dir_ + "/scalar.nrrd";
  test::writeTestNrrd(path, v, "uchar", test::encodeAs<std::uint8_t>(v.values), false, "",
                      kDirections);
  VolumeOptions o;
  o.isoValue = 110.0;
  const VolumeLoad load = loadVolume(path, o);
  ASSERT_EQ(load.kind, "scalar");
  ASSERT_TRUE(load.transform.resampled);
  const double halfWidth = kScalarRampHalfWidth * (*hi - *lo);
  const glm::ivec3 kinds = expectAsReference(
      load.grid, v, *lo, [&](double value) { return ramp(value, 110.0, halfWidth); }, nullptr);
  EXPECT_GT(kinds.x, 10000);
  EXPECT_GT(kinds.y, 300);
  EXPECT_GT(kinds.z, 10000);
}

}  // namespace
}  // namespace osteon::geometry
