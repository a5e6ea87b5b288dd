// The density rule of label maps and scalar volumes against its definition, checked voxel by
// voxel on random small volumes (fixed seeds): a voxel with bone is cancellous when the
// (2 shell + 1)^3 cube around it lies within the volume and is all inside (fill at or above
// half), cortical otherwise. deepInside computes that in three erosions; the reference here
// looks at every voxel of every cube.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/volume_grid_build.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/volume_files.h"
#include "support/volume_fixture.h"

namespace osteon::geometry {
namespace {

using test::TestVolume;

std::size_t indexOf(glm::ivec3 n, glm::ivec3 p) {
  return (std::size_t(p.z) * std::size_t(n.y) + std::size_t(p.y)) * std::size_t(n.x) +
         std::size_t(p.x);
}

// The definition, cube by cube.
bool deepByCube(glm::ivec3 n, const std::vector<bool>& inside, glm::ivec3 p, int shell) {
  for (int dz = -shell; dz <= shell; ++dz) {
    for (int dy = -shell; dy <= shell; ++dy) {
      for (int dx = -shell; dx <= shell; ++dx) {
        const glm::ivec3 q = p + glm::ivec3(dx, dy, dz);
        if (glm::any(glm::lessThan(q, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(q, n)))
          return false;
        if (!inside[indexOf(n, q)]) return false;
      }
    }
  }
  return true;
}

// Inside voxels as noise of a given share, or as a few random boxes (long runs, deep cores).
std::vector<bool> randomInside(glm::ivec3 n, std::mt19937& rng, int pattern) {
  const std::size_t count = std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z);
  std::vector<bool> inside(count, false);
  if (pattern < 4) {
    const double share[] = {0.5, 0.9, 0.99, 1.0};
    std::bernoulli_distribution in(share[pattern]);
    for (std::size_t i = 0; i < count; ++i) inside[i] = in(rng);
    return inside;
  }
  for (int box = 0; box < 3; ++box) {
    glm::ivec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      std::uniform_int_distribution<int> at(0, n[a] - 1);
      lo[a] = at(rng);
      hi[a] = at(rng);
      if (lo[a] > hi[a]) std::swap(lo[a], hi[a]);
    }
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) inside[indexOf(n, {x, y, z})] = true;
  }
  std::bernoulli_distribution hole(0.02);  // a few outside voxels within the boxes
  for (std::size_t i = 0; i < count; ++i) inside[i] = inside[i] && !hole(rng);
  return inside;
}

TEST(VolumeDensity, DeepInsideMatchesTheCubeOfEveryVoxelOnRandomVolumes) {
  std::mt19937 rng(37);
  std::uniform_int_distribution<int> edge(1, 23);
  for (int trial = 0; trial < 120; ++trial) {
    const glm::ivec3 n(edge(rng), edge(rng), edge(rng));
    const std::vector<bool> inside = randomInside(n, rng, trial % 6);
    std::vector<Fill> fills(inside.size());
    for (std::size_t i = 0; i < fills.size(); ++i) {
      // Partial fills on both sides of half: inside is fill at or above half, not fill above 0.
      fills[i] = inside[i] ? Fill(kFillHalf + (i % 3)) : Fill(i % 2 ? kFillHalf - 1 : 0);
    }
    const auto fillRow = [&](glm::ivec3, std::size_t i, int length, Fill* out) {
      std::copy_n(fills.begin() + std::ptrdiff_t(i), length, out);
    };
    for (const int shell : {1, 2, 3, 5, 12, 128}) {
      const std::unique_ptr<std::uint8_t[]> deep = deepInside(n, shell, fillRow);
      for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
          for (int x = 0; x < n.x; ++x) {
            const std::size_t i = indexOf(n, {x, y, z});
            ASSERT_EQ(deep[i] != 0, deepByCube(n, inside, {x, y, z}, shell))
                << "trial " << trial << ", sizes " << n.x << "x" << n.y << "x" << n.z << ", shell "
                << shell << ", voxel " << x << "," << y << "," << z;
          }
    }
  }
}

// Runs along a column counted in bytes (saturating) or in 32 bits (windows past 255 voxels)
// erode alike, as the definition does: every voxel of the window within the column and set.
TEST(VolumeDensity, ColumnErosionsCountInBytesOrWordsAlike) {
  std::mt19937 rng(128);
  std::uniform_int_distribution<int> length(1, 300), width(1, 9), radius(1, 140);
  std::bernoulli_distribution set(0.995);
  for (int trial = 0; trial < 60; ++trial) {
    const int n = length(rng), r = trial < 30 ? radius(rng) % 7 + 1 : radius(rng);
    const auto w = std::size_t(width(rng));
    std::vector<std::uint8_t> in(std::size_t(n) * w);
    for (auto& b : in) b = set(rng) ? 1 : 0;
    std::vector<std::uint8_t> expected(in.size());
    for (int k = 0; k < n; ++k)
      for (std::size_t x = 0; x < w; ++x) {
        bool all = k - r >= 0 && k + r < n;
        for (int j = std::max(0, k - r); all && j <= k + r; ++j) all = in[std::size_t(j) * w + x];
        expected[std::size_t(k) * w + x] = all ? 1 : 0;
      }
    std::vector<std::uint8_t> bytes = in, words = in;
    std::vector<std::uint8_t> byteRuns;
    std::vector<std::int32_t> wordRuns;
    if (2 * r + 1 <= 255) {
      erodeAcrossCounting(bytes.data(), w, n, w, r, byteRuns);
      ASSERT_EQ(bytes, expected) << "trial " << trial << ", r " << r;
    }
    erodeAcrossCounting(words.data(), w, n, w, r, wordRuns);
    ASSERT_EQ(words, expected) << "trial " << trial << ", r " << r;
  }
}

class VolumeDensityFiles : public test::VolumeFolderTest {
 protected:
  VolumeDensityFiles() : VolumeFolderTest("volume_density") {}

  // Every voxel of a load: the fill given, and the density by the rule on those fills.
  static void expectDensityByRule(const VolumeLoad& load, int shell, const std::string& what) {
    const VoxelGrid& grid = load.grid;
    const glm::ivec3 n = grid.dims();
    std::vector<bool> inside(std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z));
    for (int z = 0; z < n.z; ++z)
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x)
          inside[indexOf(n, {x, y, z})] = grid.fill({x, y, z}) >= kFillHalf;
    for (int z = 0; z < n.z; ++z)
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x) {
          const Fill fill = grid.fill({x, y, z});
          const Density expected = fill == 0                                 ? Density(0)
                                   : deepByCube(n, inside, {x, y, z}, shell) ? kCtCancellousDensity
                                                                             : kCtCorticalDensity;
          ASSERT_EQ(grid.density({x, y, z}), expected)
              << what << ", voxel " << x << "," << y << "," << z << ", fill " << fill;
        }
  }
};

TEST_F(VolumeDensityFiles, ALabelMapsDensityFollowsTheShellRuleWholeAndCropped) {
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> edge(3, 26);
  int croppedCompared = 0;
  for (int trial = 0; trial < 24; ++trial) {
    TestVolume v;
    v.sizes = {edge(rng), edge(rng), edge(rng)};
    v.spacingMm = trial % 3 == 0 ? 0.5 : trial % 3 == 1 ? 1.0 : 2.5;  // shells of 4, 2 and 1
    std::vector<bool> inside = randomInside(v.sizes, rng, 1 + trial % 5);
    inside[0] = false;  // never bone everywhere (refused)
    v.values.resize(inside.size());
    // Odd trials: 16-bit labels, bone the one named (the other non-zero label is not bone).
    const bool named = trial % 2 == 1;
    for (std::size_t i = 0; i < inside.size(); ++i)
      v.values[i] = inside[i] ? (named ? 700.0 : 255.0) : named && i % 7 == 0 ? 3.0 : 0.0;
    const std::string name = "labels" + std::to_string(trial) + ".nrrd";
    test::writeTestNrrd(
        file(name), v, named ? "ushort" : "uint8",
        named ? test::encodeAs<std::uint16_t>(v.values) : test::encodeAs<std::uint8_t>(v.values),
        false);
    const int shell = int(std::ceil(2.0 / v.spacingMm));
    VolumeOptions options;
    if (named) options.label = 700;
    const VolumeLoad whole = loadVolume(file(name), options);
    ASSERT_EQ(whole.kind, "label map");
    for (std::size_t i = 0; i < inside.size(); ++i) {
      const glm::ivec3 n = v.sizes;
      const glm::ivec3 p(int(i % std::size_t(n.x)), int(i / std::size_t(n.x) % std::size_t(n.y)),
                         int(i / (std::size_t(n.x) * std::size_t(n.y))));
      ASSERT_EQ(whole.grid.fill(p), inside[i] ? kFillFull : Fill(0)) << name;
    }
    expectDensityByRule(whole, shell, name);
    // Cropped: a grid that is not the stored one row for row (the crop's edge is outside).
    VolumeOptions cropped = options;
    const glm::dvec3 lo = v.firstCentreMm + glm::dvec3(1.0) * v.spacingMm;
    const glm::dvec3 hi = v.firstCentreMm + glm::dvec3(v.sizes - 2) * v.spacingMm;
    if (glm::any(glm::greaterThanEqual(lo, hi))) continue;
    cropped.cropMm = BoxMm{lo, hi};
    try {
      expectDensityByRule(loadVolume(file(name), cropped), shell, name + " cropped");
      ++croppedCompared;
    } catch (const InputError&) {
      // A crop that holds no outside voxel is refused as bone everywhere: nothing to compare.
    }
  }
  EXPECT_GE(croppedCompared, 12);
}

TEST_F(VolumeDensityFiles, AScalarVolumesDensityFollowsTheShellRuleOnItsRampedFills) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> edge(4, 22);
  std::uniform_real_distribution<double> noise(-30.0, 30.0);
  for (int trial = 0; trial < 12; ++trial) {
    TestVolume v;
    v.sizes = {edge(rng), edge(rng), edge(rng)};
    v.spacingMm = trial % 2 == 0 ? 0.5 : 1.0;
    const std::vector<bool> inside = randomInside(v.sizes, rng, 4 + trial % 2);
    v.values.resize(inside.size());
    for (std::size_t i = 0; i < inside.size(); ++i)
      v.values[i] = (inside[i] ? 180.0 : 60.0) + noise(rng);  // ramps give partial fills
    v.values[0] = 0.0;
    // Odd trials 16-bit (each stored value's fill looked up), even ones float (worked out).
    const bool uint16 = trial % 2 == 1;
    if (uint16)
      for (double& value : v.values) value = double(std::uint16_t(value));
    const std::string name = "scalar" + std::to_string(trial) + ".nrrd";
    test::writeTestNrrd(
        file(name), v, uint16 ? "ushort" : "float",
        uint16 ? test::encodeAs<std::uint16_t>(v.values) : test::encodeAs<float>(v.values), false);
    VolumeOptions o;
    o.isoValue = 120.0;
    const VolumeLoad load = loadVolume(file(name), o);
    ASSERT_EQ(load.kind, "scalar");
    const double halfWidth = load.rampHalfWidth;
    ASSERT_GT(halfWidth, 0.0);
    for (std::size_t i = 0; i < v.values.size(); ++i) {
      const double t = (double(float(v.values[i])) - (120.0 - halfWidth)) / (2.0 * halfWidth);
      const glm::ivec3 n = v.sizes;
      const glm::ivec3 p(int(i % std::size_t(n.x)), int(i / std::size_t(n.x) % std::size_t(n.y)),
                         int(i / (std::size_t(n.x) * std::size_t(n.y))));
      ASSERT_EQ(load.grid.fill(p), Fill(std::lround(std::clamp(t, 0.0, 1.0) * kFillFull)))
          << name << ", value " << v.values[i];
    }
    expectDensityByRule(load, int(std::ceil(2.0 / v.spacingMm)), name);
  }
}

// A CT voxel by the rule: fill ramped from iso - 100 HU to iso + 100 HU, cortical from 800 HU.
void expectCtVoxels(const VolumeLoad& load, const TestVolume& v, glm::ivec3 offset, double iso,
                    const std::string& what) {
  const glm::ivec3 n = load.grid.dims();
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        const glm::ivec3 q = glm::ivec3(x, y, z) + offset;
        const double hu = v.values[indexOf(v.sizes, q)];
        const double t = (hu - (iso - kCtRampHalfWidthHu)) / (2.0 * kCtRampHalfWidthHu);
        const auto fill = Fill(std::lround(std::clamp(t, 0.0, 1.0) * kFillFull));
        const Density density = fill == 0           ? Density(0)
                                : hu >= kCorticalHu ? kCtCorticalDensity
                                                    : kCtCancellousDensity;
        ASSERT_EQ(load.grid.fill({x, y, z}), fill) << what << ", HU " << hu;
        ASSERT_EQ(load.grid.density({x, y, z}), density) << what << ", HU " << hu;
      }
}

TEST_F(VolumeDensityFiles, ACtsFillAndDensityFollowTheHuRuleForEveryStoredType) {
  std::mt19937 rng(300);
  std::uniform_int_distribution<int> edge(4, 20);
  std::uniform_int_distribution<int> hu(-1024, 3000);
  for (int trial = 0; trial < 6; ++trial) {
    TestVolume v;
    v.sizes = {edge(rng), edge(rng), edge(rng)};
    v.values.resize(std::size_t(v.sizes.x) * std::size_t(v.sizes.y) * std::size_t(v.sizes.z));
    for (double& value : v.values) value = hu(rng);
    v.values[0] = -1024.0;
    v.values[1] = 3000.0;  // a CT's range
    const std::string name = "ct" + std::to_string(trial);
    // int16 (every stored value's voxel looked up), float (worked out voxel by voxel).
    test::writeTestNrrd(file(name + "s.nrrd"), v, "short", test::encodeAs<std::int16_t>(v.values),
                        false);
    test::writeTestNrrd(file(name + "f.nrrd"), v, "float", test::encodeAs<float>(v.values), false);
    VolumeOptions o;
    o.isoValue = 250.0 + 40.0 * trial;
    for (const char* type : {"s", "f"}) {
      const VolumeLoad load = loadVolume(file(name + type + ".nrrd"), o);
      ASSERT_EQ(load.kind, "ct");
      expectCtVoxels(load, v, glm::ivec3(0), *o.isoValue, name + type);
    }
    // Cropped: rows start inside the stored ones.
    VolumeOptions cropped = o;
    cropped.cropMm = BoxMm{glm::dvec3(1.0), glm::dvec3(v.sizes - 2)};
    const VolumeLoad load = loadVolume(file(name + "s.nrrd"), cropped);
    ASSERT_EQ(load.grid.dims(), v.sizes - 2);
    expectCtVoxels(load, v, glm::ivec3(1), *o.isoValue, name + " cropped");
  }
}

}  // namespace
}  // namespace osteon::geometry
