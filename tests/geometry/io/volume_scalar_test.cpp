// Any scalar volume with an iso value (micro-CT, probability maps), float masks, empty volumes,
// and crops (a box in mm, a label's box with a margin), through loadVolume.
#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/core/option_error.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"
#include "support/volume_files.h"
#include "support/volume_fixture.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;
using test::TestVolume;

class VolumeScalar : public test::VolumeFolderTest {
 protected:
  VolumeScalar() : VolumeFolderTest("volume_scalar") {}
};

// 24^3 voxels of 0.5 mm from (0.25, 0.25, 0.25); a 12^3 cube of `inside` in voxels 6..17, the
// rest `outside` plus a ramp of `spread` over x (many distinct values, as a scan has).
TestVolume cube(double inside, double outside, double spread = 0.0) {
  TestVolume v;
  v.sizes = glm::ivec3(24);
  v.spacingMm = 0.5;
  v.firstCentreMm = glm::dvec3(0.25);
  for (int z = 0; z < 24; ++z) {
    for (int y = 0; y < 24; ++y) {
      for (int x = 0; x < 24; ++x) {
        const bool in = x >= 6 && x < 18 && y >= 6 && y < 18 && z >= 6 && z < 18;
        v.values.push_back((in ? inside : outside) + spread * (x + 24 * y) / 576.0);
      }
    }
  }
  return v;
}

TEST_F(VolumeScalar, AUint8MicroCtIsBoneAboveTheIsoValueItsDensityByDistance) {
  const TestVolume v = cube(160.0, 20.0, 70.0);  // bone 160-230, background 20-90
  test::writeTestNrrd(file("micro.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), true);
  const std::string m = refusal("micro.nrrd");
  EXPECT_NE(m.find("neither a label map nor a CT: uint8"), std::string::npos) << m;
  EXPECT_NE(m.find("volume.isoValue reads any volume"), std::string::npos) << m;
  VolumeOptions o;
  o.isoValue = 110.0;
  const VolumeLoad load = loadVolume(file("micro.nrrd"), o);
  EXPECT_EQ(load.kind, "scalar");
  EXPECT_DOUBLE_EQ(load.isoValue, 110.0);
  EXPECT_EQ(load.grid.countVoxels(kFillHalf), 12u * 12u * 12u);
  EXPECT_EQ(load.grid.fill({6, 6, 6}), kFillFull);
  EXPECT_EQ(load.grid.fill({5, 6, 6}), 0);
  EXPECT_EQ(load.grid.density({6, 6, 6}), kCtCorticalDensity);       // at the surface
  EXPECT_EQ(load.grid.density({12, 12, 12}), kCtCancellousDensity);  // 6 voxels (3 mm) deep
  EXPECT_FALSE(load.transform.resampled);
  EXPECT_EQ(load.transform.interpolation, "none");
}

TEST_F(VolumeScalar, AFloatProbabilityMapIsBoneAboveHalf) {
  const TestVolume v = cube(0.9, 0.05, 0.05);
  test::writeTestNrrd(file("p.nrrd"), v, "float", test::encodeAs<float>(v.values), false);
  EXPECT_NE(refusal("p.nrrd").find("neither"), std::string::npos);
  VolumeOptions o;
  o.isoValue = 0.5;
  const VolumeLoad load = loadVolume(file("p.nrrd"), o);
  EXPECT_EQ(load.kind, "scalar");
  EXPECT_EQ(load.grid.countVoxels(kFillHalf), 12u * 12u * 12u);
  // Values that would make a label map (a 0/1 mask) are levels once an iso value is given.
  const TestVolume labels = cube(1.0, 0.0);
  test::writeTestNrrd(file("l.nrrd"), labels, "uint8", test::encodeAs<std::uint8_t>(labels.values),
                      false);
  EXPECT_EQ(loadVolume(file("l.nrrd")).kind, "label map");
  const VolumeLoad mask = loadVolume(file("l.nrrd"), o);
  EXPECT_EQ(mask.kind, "scalar");
  EXPECT_EQ(mask.grid.countVoxels(kFillHalf), 12u * 12u * 12u);
  // An all-zero map with an iso value holds no bone: an empty grid, not a refusal.
  const TestVolume zero = cube(0.0, 0.0);
  test::writeTestNrrd(file("z.nrrd"), zero, "double", test::encodeAs<double>(zero.values), true);
  const VolumeLoad none = loadVolume(file("z.nrrd"), o);
  EXPECT_EQ(none.kind, "scalar");
  EXPECT_EQ(none.grid.countVoxels(1), 0u);
}

TEST_F(VolumeScalar, AnAllZeroFloatVolumeIsALabelMapWithNoBone) {
  const TestVolume v = cube(0.0, 0.0);
  test::writeTestNrrd(file("zero.nrrd"), v, "double", test::encodeAs<double>(v.values), true);
  const VolumeLoad load = loadVolume(file("zero.nrrd"));
  EXPECT_EQ(load.kind, "label map");
  EXPECT_EQ(load.grid.countVoxels(kFillHalf), 0u);
}

TEST_F(VolumeScalar, ACropKeepsTheVoxelsWhoseCentresLieInItsBox) {
  const TestVolume v = cube(1.0, 0.0);
  test::writeTestNrrd(file("l.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false);
  VolumeOptions o;
  o.cropMm = BoxMm{{0.0, 0.0, 0.0}, {6.0, 12.0, 12.0}};  // x: voxels 0..11
  const VolumeLoad half = loadVolume(file("l.nrrd"), o);
  EXPECT_EQ(half.grid.dims(), glm::ivec3(12, 24, 24));
  EXPECT_TRUE(half.transform.cropped);
  EXPECT_EQ(half.grid.countVoxels(kFillHalf), 6u * 12u * 12u);
  o.cropMm = BoxMm{{2.0, 2.0, 2.0}, {4.0, 4.0, 4.0}};  // voxels 4..7 each way
  const VolumeLoad inner = loadVolume(file("l.nrrd"), o);
  EXPECT_EQ(inner.grid.dims(), glm::ivec3(4));
  EXPECT_NEAR(inner.grid.originMm().x, 2.0, 1e-9);
  EXPECT_EQ(inner.grid.fill({2, 2, 2}), kFillFull);  // voxel 6: inside the cube
  EXPECT_EQ(inner.grid.fill({1, 1, 1}), 0);
  o.cropMm = BoxMm{{100.0, 0.0, 0.0}, {110.0, 1.0, 1.0}};
  EXPECT_NE(refusal("l.nrrd", o).find("holds no voxel of the volume, which spans 0:12,0:12,0:12"),
            std::string::npos)
      << refusal("l.nrrd", o);
}

TEST_F(VolumeScalar, ACropToALabelTakesItsBoxAndTheMargin) {
  TestVolume v = cube(1.0, 0.0);
  v.values[0] = 2.0;  // one voxel of label 2 at the corner
  test::writeTestNrrd(file("l.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false);
  VolumeOptions o;
  o.cropToLabel = 1;
  o.cropMarginMm = 1.0;  // two voxels either side of 6..17
  const VolumeLoad load = loadVolume(file("l.nrrd"), o);
  EXPECT_EQ(load.grid.dims(), glm::ivec3(16));
  EXPECT_NEAR(load.grid.originMm().x, 2.0, 1e-9);
  EXPECT_EQ(load.grid.countVoxels(kFillHalf), 12u * 12u * 12u);
  o.cropToLabel = 7;
  EXPECT_NE(refusal("l.nrrd", o).find("volume.cropToLabel 7 is not in the label map"),
            std::string::npos);
  const TestVolume ct = cube(1000.0, -1000.0);
  test::writeTestNrrd(file("ct.nrrd"), ct, "short", test::encodeAs<std::int16_t>(ct.values), false);
  o.cropToLabel = 1;
  EXPECT_NE(refusal("ct.nrrd", o).find("volume.cropToLabel is for label maps"), std::string::npos);
}

TEST_F(VolumeScalar, OptionsAreCheckedBeforeReadingAndNamedByTheirFields) {
  VolumeOptions o;
  o.voxelSizeMm = 0.0;
  try {
    loadVolume(file("missing.nrrd"), o);
    FAIL();
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), "volume.voxelSizeMm");
  }
  o = {};
  o.cropMm = BoxMm{{1.0, 0.0, 0.0}, {0.0, 1.0, 1.0}};
  try {
    loadVolume(file("missing.nrrd"), o);
    FAIL();
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), "volume.cropMm");
  }
}

}  // namespace
}  // namespace osteon::geometry
