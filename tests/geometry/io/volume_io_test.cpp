#include "osteon/geometry/io/volume_io.h"

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "support/files.h"
#include "support/shapes.h"
#include "support/volume_files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;
using test::TestVolume;

class VolumeIo : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("volume");
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return dir_ + "/" + name; }
};

// 8^3 voxels of 0.5 mm; a 4^3 cube of `inside` in the middle, `outside` around it.
TestVolume cube(double inside, double outside) {
  TestVolume v;
  v.sizes = {8, 8, 8};
  v.spacingMm = 0.5;
  v.firstCentreMm = {10.25, -4.75, 3.25};
  v.values.assign(512, outside);
  for (int z = 2; z < 6; ++z) {
    for (int y = 2; y < 6; ++y) {
      for (int x = 2; x < 6; ++x) v.values[std::size_t((z * 8 + y) * 8 + x)] = inside;
    }
  }
  return v;
}

void expectCubeGrid(const VolumeLoad& load) {
  const VoxelGrid& g = load.grid;
  EXPECT_EQ(g.dims(), glm::ivec3(8, 8, 8));
  EXPECT_DOUBLE_EQ(g.voxelSizeMm(), 0.5);
  EXPECT_NEAR(g.originMm().x, 10.0, 1e-5);
  EXPECT_NEAR(g.originMm().y, -5.0, 1e-5);
  EXPECT_NEAR(g.originMm().z, 3.0, 1e-5);
  EXPECT_EQ(g.countVoxels(kFillHalf), 64u);
  EXPECT_EQ(g.fill({3, 3, 3}), kFillFull);
  EXPECT_EQ(g.fill({0, 0, 0}), 0);
  EXPECT_GT(g.density({3, 3, 3}), 0);
}

TEST_F(VolumeIo, LabelMapNrrdRawGzipAttachedAndDetached) {
  const TestVolume v = cube(1, 0);
  const std::string bytes = test::encodeAs<std::uint8_t>(v.values);
  test::writeTestNrrd(file("raw.nrrd"), v, "uchar", bytes, false);
  test::writeTestNrrd(file("gz.nrrd"), v, "uint8", bytes, true);
  test::writeTestNrrd(file("det.nhdr"), v, "unsigned char", bytes, false, "det.raw");
  test::writeTestNrrd(file("detgz.nhdr"), v, "uint8", bytes, true, "detgz.raw.gz");
  for (const char* name : {"raw.nrrd", "gz.nrrd", "det.nhdr", "detgz.nhdr"}) {
    SCOPED_TRACE(name);
    const VolumeLoad load = loadVolume(file(name));
    EXPECT_EQ(load.kind, "label map");
    EXPECT_EQ(load.type, "uint8");
    EXPECT_EQ(load.labels, (std::vector<std::uint64_t>{0, 1}));
    EXPECT_FALSE(load.label.has_value());
    expectCubeGrid(load);
  }
}

TEST_F(VolumeIo, EveryScalarTypeReadsTheSameLabelMap) {
  const TestVolume v = cube(1, 0);
  const std::vector<std::pair<std::string, std::string>> types = {
      {"int8", test::encodeAs<std::int8_t>(v.values)},
      {"uint8", test::encodeAs<std::uint8_t>(v.values)},
      {"short", test::encodeAs<std::int16_t>(v.values)},
      {"ushort", test::encodeAs<std::uint16_t>(v.values)},
      {"int", test::encodeAs<std::int32_t>(v.values)},
      {"uint", test::encodeAs<std::uint32_t>(v.values)},
      {"int64", test::encodeAs<std::int64_t>(v.values)},
      {"uint64", test::encodeAs<std::uint64_t>(v.values)}};
  for (const auto& [type, bytes] : types) {
    SCOPED_TRACE(type);
    test::writeTestNrrd(file(type + ".nrrd"), v, type, bytes, true);
    const VolumeLoad load = loadVolume(file(type + ".nrrd"));
    EXPECT_EQ(load.kind, "label map");
    expectCubeGrid(load);
  }
  // Floats whose values are all whole are labels too (masks saved as float or double).
  test::writeTestNrrd(file("f.nrrd"), v, "float", test::encodeAs<float>(v.values), false);
  test::writeTestNrrd(file("d.nrrd"), v, "double", test::encodeAs<double>(v.values), true);
  for (const char* name : {"f.nrrd", "d.nrrd"}) {
    SCOPED_TRACE(name);
    const VolumeLoad load = loadVolume(file(name));
    EXPECT_EQ(load.kind, "label map");
    EXPECT_EQ(load.labels, (std::vector<std::uint64_t>{0, 1}));
    expectCubeGrid(load);
  }
  // A float with a fraction among few values is no label map: neither, unless an iso is given.
  TestVolume half = v;
  half.values[0] = 0.5;
  test::writeTestNrrd(file("h.nrrd"), half, "float", test::encodeAs<float>(half.values), false);
  try {
    loadVolume(file("h.nrrd"));
    FAIL() << "a float volume with a fractional value was read as labels";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("h.nrrd"), std::string::npos) << m;
    EXPECT_NE(m.find("neither a label map nor a CT"), std::string::npos) << m;
    EXPECT_NE(m.find("3 distinct values"), std::string::npos) << m;
  }
  VolumeOptions iso;
  iso.isoValue = 0.75;
  const VolumeLoad scalar = loadVolume(file("h.nrrd"), iso);
  EXPECT_EQ(scalar.kind, "scalar");
  expectCubeGrid(scalar);
}

TEST_F(VolumeIo, LabelsPickTheBone) {
  TestVolume v = cube(1, 0);
  v.values[0] = 2;  // a second structure: one voxel of label 2
  test::writeTestNrrd(file("l.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false);
  const VolumeLoad all = loadVolume(file("l.nrrd"));
  EXPECT_EQ(all.labels, (std::vector<std::uint64_t>{0, 1, 2}));
  EXPECT_EQ(all.grid.countVoxels(kFillHalf), 65u);
  VolumeOptions two;
  two.label = 2;
  EXPECT_EQ(loadVolume(file("l.nrrd"), two).grid.countVoxels(kFillHalf), 1u);
  VolumeOptions one;
  one.label = 1;
  EXPECT_EQ(loadVolume(file("l.nrrd"), one).grid.countVoxels(kFillHalf), 64u);
  VolumeOptions missing;
  missing.label = 7;
  try {
    loadVolume(file("l.nrrd"), missing);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("labels found: 0, 1, 2"), std::string::npos) << e.what();
  }
  // An iso value reads the labels as levels: none is above 200, so there is no bone.
  VolumeOptions iso;
  iso.isoValue = 200;
  const VolumeLoad levels = loadVolume(file("l.nrrd"), iso);
  EXPECT_EQ(levels.kind, "scalar");
  EXPECT_EQ(levels.grid.countVoxels(1), 0u);
}

TEST_F(VolumeIo, NiftiPlainAndGzipMatchNrrd) {
  const TestVolume v = cube(1, 0);
  const std::string bytes = test::encodeAs<std::uint8_t>(v.values);
  test::writeTestNifti(file("a.nii"), v, 2, 8, bytes, false);
  test::writeTestNifti(file("a.nii.gz"), v, 2, 8, bytes, true);
  for (const char* name : {"a.nii", "a.nii.gz"}) {
    SCOPED_TRACE(name);
    const VolumeLoad load = loadVolume(file(name));
    EXPECT_EQ(load.format, "nifti");
    EXPECT_EQ(load.kind, "label map");
    expectCubeGrid(load);
  }
}

// int16 HU: -1000 air around a 900 HU cube with noise; the surface sits at the iso level.
TEST_F(VolumeIo, Int16CtThresholdsAtIsoAndDensityFromHu) {
  TestVolume v = cube(900, -1000);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 20.0);
  for (double& x : v.values) x = std::round(x + noise(rng));
  v.values[std::size_t((3 * 8 + 3) * 8 + 3)] = 500;  // one cancellous voxel inside
  const std::string bytes = test::encodeAs<std::int16_t>(v.values);
  test::writeTestNrrd(file("ct.nrrd"), v, "short", bytes, true);
  test::writeTestNifti(file("ct.nii.gz"), v, 4, 16, bytes, true);
  for (const char* name : {"ct.nrrd", "ct.nii.gz"}) {
    SCOPED_TRACE(name);
    const VolumeLoad load = loadVolume(file(name));
    EXPECT_EQ(load.kind, "ct");
    EXPECT_EQ(load.type, "int16");
    EXPECT_DOUBLE_EQ(load.isoValue, kDefaultIsoHu);
    expectCubeGrid(load);
    EXPECT_EQ(load.grid.density({2, 2, 2}), kCtCorticalDensity);
    EXPECT_EQ(load.grid.density({3, 3, 3}), kCtCancellousDensity);
    EXPECT_GT(kCtCorticalDensity, kCtCancellousDensity);  // cortical bone wears slower
  }
  // The same HU as float (as some pipelines save CTs): a CT too.
  test::writeTestNrrd(file("ctf.nrrd"), v, "float", test::encodeAs<float>(v.values), true);
  const VolumeLoad f = loadVolume(file("ctf.nrrd"));
  EXPECT_EQ(f.kind, "ct");
  EXPECT_EQ(f.type, "float");
  expectCubeGrid(f);
  // The ramp: fill is half exactly at the iso level.
  TestVolume ramp = cube(300, -1000);
  ramp.values[1] = 1000;  // range >= 1000 and many values: a CT
  for (std::size_t i = 0; i < 100; ++i) ramp.values[100 + i] = -1000 + double(i);
  test::writeTestNrrd(file("ramp.nrrd"), ramp, "short", test::encodeAs<std::int16_t>(ramp.values),
                      false);
  const VolumeLoad r = loadVolume(file("ramp.nrrd"));
  ASSERT_EQ(r.kind, "ct");
  EXPECT_EQ(r.grid.fill({3, 3, 3}), kFillHalf);
  VolumeOptions high;
  high.isoValue = 1000;
  EXPECT_EQ(loadVolume(file("ramp.nrrd"), high).grid.fill({3, 3, 3}), 0);
  VolumeOptions label;
  label.label = 1;
  EXPECT_THROW(loadVolume(file("ramp.nrrd"), label), InputError);
}

TEST_F(VolumeIo, SpaceDirectionsAreHonouredAndRotationsRefused) {
  TestVolume v = cube(1, 0);
  v.values[0] = 2;  // marks voxel (0,0,0) as stored
  const std::string bytes = test::encodeAs<std::uint8_t>(v.values);
  // x runs backwards: stored voxel 0 lies at the high x end.
  test::writeTestNrrd(file("flip.nrrd"), v, "uint8", bytes, false, "",
                      "(-0.5,0,0) (0,0.5,0) (0,0,0.5)");
  VolumeOptions two;
  two.label = 2;
  const VolumeLoad flipped = loadVolume(file("flip.nrrd"), two);
  EXPECT_EQ(flipped.grid.fill({7, 0, 0}), kFillFull);
  EXPECT_NEAR(flipped.grid.originMm().x, 10.25 - 3.5 - 0.25, 1e-5);
  // Rotated or anisotropic voxels are resampled onto cubic LPS voxels (volume_resample_test.cpp).
  test::writeTestNrrd(file("aniso.nrrd"), v, "uint8", bytes, false, "",
                      "(0.5,0,0) (0,0.5,0) (0,0,1)");
  const VolumeLoad aniso = loadVolume(file("aniso.nrrd"), two);
  EXPECT_TRUE(aniso.transform.resampled);
  EXPECT_EQ(aniso.grid.dims(), glm::ivec3(8, 8, 16));
  EXPECT_DOUBLE_EQ(aniso.grid.voxelSizeMm(), 0.5);
}

TEST_F(VolumeIo, TruncatedAndCorruptDataAreRefused) {
  const TestVolume v = cube(1, 0);
  std::string bytes = test::encodeAs<std::uint8_t>(v.values);
  test::writeTestNrrd(file("short.nrrd"), v, "uint8", bytes.substr(0, 100), false);
  EXPECT_THROW(loadVolume(file("short.nrrd")), InputError);
  test::writeTestNrrd(file("shortgz.nrrd"), v, "uint8", bytes.substr(0, 100), true);
  EXPECT_THROW(loadVolume(file("shortgz.nrrd")), InputError);
  test::writeTestNrrd(file("nodata.nhdr"), v, "uint8", bytes, false, "x.raw");
  fs::remove(file("x.raw"));
  EXPECT_THROW(loadVolume(file("nodata.nhdr")), InputError);
  test::writeBytes(file("bad.nii"), std::string(100, 'x'));
  EXPECT_THROW(loadVolume(file("bad.nii")), InputError);
  // Sizes asking for 2^32 voxels over a few bytes: refused before anything that large is allocated.
  TestVolume huge = v;
  huge.sizes = {2048, 2048, 1024};
  test::writeTestNrrd(file("huge.nrrd"), huge, "double", bytes, true);
  test::writeTestNifti(file("huge.nii.gz"), huge, 64, 64, bytes, true);
  test::writeTestNifti(file("huge.nii"), huge, 64, 64, bytes, false);
  for (const char* name : {"huge.nrrd", "huge.nii.gz", "huge.nii"}) {
    SCOPED_TRACE(name);
    try {
      loadVolume(file(name));
      FAIL();
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
  }
}

TEST_F(VolumeIo, OsteonGridsLoadAsToday) {
  VoxelGrid grid({20, 20, 20}, glm::dvec3(1, 2, 3), 0.75);
  for (int z = 5; z < 15; ++z) {
    for (int y = 5; y < 15; ++y) {
      for (int x = 5; x < 15; ++x) grid.set({x, y, z}, kFillFull, 33);
    }
  }
  writeNrrd(grid, file("g.nrrd"));
  const VolumeLoad load = loadVolume(file("g.nrrd"));
  EXPECT_EQ(load.kind, "osteon grid");
  EXPECT_TRUE(load.densityLoaded);
  EXPECT_EQ(load.grid.countVoxels(kFillHalf), 1000u);
  EXPECT_EQ(load.grid.density({7, 7, 7}), 33);
  VolumeOptions label;
  label.label = 1;
  EXPECT_THROW(loadVolume(file("g.nrrd"), label), InputError);
}

// The built-in humerus voxelized, then written as a label map and as a noisy CT, seeded.
TEST_F(VolumeIo, BuiltInBoneAsLabelMapAndCt) {
  VoxelizeOptions vo;
  vo.voxelSizeMm = 2.0;
  const VoxelGrid bone = voxelize(buildHumerusModel().mesh, vo);
  TestVolume v;
  v.sizes = bone.dims();
  v.spacingMm = bone.voxelSizeMm();
  v.firstCentreMm = bone.voxelCentreMm(glm::ivec3(0));
  std::vector<double> labels, hu;
  std::mt19937 rng(22);
  std::normal_distribution<double> noise(0.0, 25.0);
  std::uint64_t cortical = 0;
  for (int z = 0; z < v.sizes.z; ++z) {
    for (int y = 0; y < v.sizes.y; ++y) {
      for (int x = 0; x < v.sizes.x; ++x) {
        const bool in = bone.fill({x, y, z}) >= kFillHalf;
        const bool cort = in && bone.density({x, y, z}) == vo.density.corticalDensity;
        cortical += cort;
        labels.push_back(in ? 1 : 0);
        hu.push_back(std::round((in ? (cort ? 1400.0 : 450.0) : -800.0) + noise(rng)));
      }
    }
  }
  v.values = labels;
  test::writeTestNrrd(file("labels.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(labels), true);
  v.values = hu;
  test::writeTestNifti(file("ct.nii.gz"), v, 4, 16, test::encodeAs<std::int16_t>(hu), true);
  const VolumeLoad l = loadVolume(file("labels.nrrd"));
  EXPECT_EQ(l.kind, "label map");
  EXPECT_EQ(l.grid.countVoxels(kFillHalf), bone.countVoxels(kFillHalf));
  const VolumeLoad c = loadVolume(file("ct.nii.gz"));
  EXPECT_EQ(c.kind, "ct");
  EXPECT_NEAR(double(c.grid.countVoxels(kFillHalf)), double(bone.countVoxels(kFillHalf)),
              0.01 * double(bone.countVoxels(kFillHalf)));
  std::uint64_t dense = 0;
  for (int z = 0; z < v.sizes.z; ++z) {
    for (int y = 0; y < v.sizes.y; ++y) {
      for (int x = 0; x < v.sizes.x; ++x) dense += c.grid.density({x, y, z}) == kCtCorticalDensity;
    }
  }
  EXPECT_EQ(dense, cortical);
}

}  // namespace
}  // namespace osteon::geometry
