// What a volume's voxels mean: non-finite values refused wherever they sit, a label map's
// background, CTs of few values, a volume that is bone everywhere, 64-bit labels kept exact,
// axes stored in another order, and NIfTI headers that disagree with themselves.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"
#include "support/shapes.h"
#include "support/volume_files.h"
#include "support/volume_fixture.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;
using test::TestVolume;

class VolumeValues : public test::VolumeFolderTest {
 protected:
  VolumeValues() : VolumeFolderTest("volume_values") {}
};

TestVolume box(glm::ivec3 sizes, double value) {
  TestVolume v;
  v.sizes = sizes;
  v.spacingMm = 0.5;
  v.firstCentreMm = {10.25, -4.75, 3.25};
  v.values.assign(std::size_t(sizes.x) * std::size_t(sizes.y) * std::size_t(sizes.z), value);
  return v;
}

std::size_t at(const TestVolume& v, int i, int j, int k) {
  return (std::size_t(k) * std::size_t(v.sizes.y) + std::size_t(j)) * std::size_t(v.sizes.x) +
         std::size_t(i);
}

// Little-endian bytes of exact 64-bit integers (encodeAs goes through double).
template <typename T>
std::string bytesOf(const std::vector<T>& values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(&bytes[0], values.data(), bytes.size());
  return bytes;
}

TEST_F(VolumeValues, NonFiniteVoxelsAnywhereAreRefusedWithTheirCountAndFirstPosition) {
  // A CT whose first voxel is fine: the NaN and the infinities sit in the middle.
  TestVolume v = box({6, 5, 4}, -1000.0);
  for (int k = 1; k < 3; ++k) {
    for (int j = 1; j < 4; ++j) {
      for (int i = 1; i < 5; ++i) v.values[at(v, i, j, k)] = 1200.0;
    }
  }
  v.values[at(v, 3, 2, 1)] = std::numeric_limits<double>::quiet_NaN();
  v.values[at(v, 4, 4, 3)] = -std::numeric_limits<double>::infinity();
  test::writeTestNrrd(file("f.nrrd"), v, "float", test::encodeAs<float>(v.values), true);
  test::writeTestNrrd(file("d.nhdr"), v, "double", test::encodeAs<double>(v.values), false,
                      "d.raw");
  test::writeTestNifti(file("f.nii.gz"), v, 16, 32, test::encodeAs<float>(v.values), true);
  test::writeTestNifti(file("d.nii"), v, 64, 64, test::encodeAs<double>(v.values), false);
  for (const char* name : {"f.nrrd", "d.nhdr", "f.nii.gz", "d.nii"}) {
    SCOPED_TRACE(name);
    const std::string m = refusal(name);
    EXPECT_NE(m.find(name), std::string::npos) << m;
    EXPECT_NE(m.find("2 of 120 voxels are not a finite number"), std::string::npos) << m;
    EXPECT_NE(m.find("the first (NaN) at voxel (3, 2, 1)"), std::string::npos) << m;
  }
  // Finite doubles that scl_slope scales past any double are no numbers either.
  TestVolume huge = v;
  huge.values[at(huge, 3, 2, 1)] = 1e308;
  huge.values[at(huge, 4, 4, 3)] = -1000.0;
  test::writeTestNifti(file("scaled.nii"), huge, 64, 64, test::encodeAs<double>(huge.values),
                       false);
  std::string scaled = test::readBytes(file("scaled.nii"));
  const float slope = 10.0f;
  std::memcpy(&scaled[112], &slope, sizeof slope);
  test::writeBytes(file("scaled.nii"), scaled);
  EXPECT_NE(refusal("scaled.nii")
                .find("scl_slope 10 and scl_inter 0 scale values -1000 to 1e+308 past any number"),
            std::string::npos)
      << refusal("scaled.nii");
  // Without them the same volume loads as the CT it is.
  v.values[at(v, 3, 2, 1)] = 1200.0;
  v.values[at(v, 4, 4, 3)] = -1000.0;
  test::writeTestNifti(file("ok.nii"), v, 16, 32, test::encodeAs<float>(v.values), false);
  const VolumeLoad ok = loadVolume(file("ok.nii"));
  EXPECT_EQ(ok.kind, "ct");
  EXPECT_EQ(ok.grid.countVoxels(kFillHalf), 24u);
}

TEST_F(VolumeValues, ALabelMapsBackgroundIsZeroOrElseItsMostCommonValue) {
  // Labels 1 (the surroundings) and 2 (a 2x2x2 block), no 0: the bone is the block.
  TestVolume v = box({6, 6, 6}, 1.0);
  for (int k = 2; k < 4; ++k) {
    for (int j = 2; j < 4; ++j) {
      for (int i = 2; i < 4; ++i) v.values[at(v, i, j, k)] = 2.0;
    }
  }
  test::writeTestNrrd(file("l12.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false);
  const VolumeLoad l = loadVolume(file("l12.nrrd"));
  EXPECT_EQ(l.kind, "label map");
  EXPECT_EQ(l.labels, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(l.background, 1u);
  EXPECT_EQ(l.grid.countVoxels(kFillHalf), 8u);
  EXPECT_EQ(l.grid.fill({2, 2, 2}), kFillFull);
  EXPECT_EQ(l.grid.fill({0, 0, 0}), 0);
  // 0 present, even as the rarer value: 0 is the background.
  TestVolume z = box({6, 6, 6}, 5.0);
  z.values[at(z, 0, 0, 0)] = 0.0;
  test::writeTestNrrd(file("l05.nrrd"), z, "uint16", test::encodeAs<std::uint16_t>(z.values),
                      false);
  const VolumeLoad l05 = loadVolume(file("l05.nrrd"));
  EXPECT_EQ(l05.background, 0u);
  EXPECT_EQ(l05.grid.countVoxels(kFillHalf), 215u);
  // One value everywhere is its own background: no bone (an empty result, not the whole box).
  test::writeTestNrrd(file("ones.nrrd"), box({6, 6, 6}, 1.0), "uint8",
                      test::encodeAs<std::uint8_t>(box({6, 6, 6}, 1.0).values), false);
  EXPECT_EQ(loadVolume(file("ones.nrrd")).grid.countVoxels(1), 0u);
  // --label naming that one value asks for a box of bone: refused, saying what was read.
  VolumeOptions one;
  one.label = 1;
  const std::string m = refusal("ones.nrrd", one);
  EXPECT_NE(m.find("ones.nrrd: every voxel is bone: read as a label map (uint8, labels 1), bone = "
                   "volume.label 1"),
            std::string::npos)
      << m;
}

TEST_F(VolumeValues, SignedVolumesWithNegativeValuesAreCtsNeverLabelMaps) {
  // +-1000 HU, two values, bone the majority (a 7^3 block in 8^3): bone is the +1000 voxels.
  TestVolume v = box({8, 8, 8}, -1000.0);
  for (int k = 0; k < 7; ++k) {
    for (int j = 0; j < 7; ++j) {
      for (int i = 0; i < 7; ++i) v.values[at(v, i, j, k)] = 1000.0;
    }
  }
  test::writeTestNrrd(file("pm.nrrd"), v, "short", test::encodeAs<std::int16_t>(v.values), true);
  test::writeTestNifti(file("pm.nii"), v, 4, 16, test::encodeAs<std::int16_t>(v.values), false);
  for (const char* name : {"pm.nrrd", "pm.nii"}) {
    SCOPED_TRACE(name);
    const VolumeLoad load = loadVolume(file(name));
    EXPECT_EQ(load.kind, "ct");
    EXPECT_EQ(load.grid.countVoxels(kFillHalf), 343u);
    EXPECT_EQ(load.grid.fill({7, 7, 7}), 0);
  }
  // All air (-1024 HU): not a label map whose every non-zero voxel is bone; neither, said so.
  const TestVolume air = box({8, 8, 8}, -1024.0);
  test::writeTestNrrd(file("air.nrrd"), air, "short", test::encodeAs<std::int16_t>(air.values),
                      true);
  const std::string m = refusal("air.nrrd");
  EXPECT_NE(m.find("neither a label map nor a CT: int16, values -1024 to -1024, 1 distinct value"),
            std::string::npos)
      << m;
  // A CT wholly at or above the iso level is bone everywhere: refused.
  VolumeOptions low;
  low.isoValue = -2000;
  const std::string all = refusal("pm.nrrd", low);
  EXPECT_NE(all.find("every voxel is bone: read as a CT (int16, values -1000 to 1000 HU), all at "
                     "or above the iso "
                     "level -2000 HU (volume.isoValue)"),
            std::string::npos)
      << all;
}

TEST_F(VolumeValues, SixtyFourBitLabelsStayExact) {
  const std::int64_t big = std::int64_t(1) << 53;
  std::vector<std::int64_t> signedLabels(64, 0);
  for (int i = 20; i < 28; ++i) signedLabels[std::size_t(i)] = big;
  signedLabels[40] = big + 1;  // a double cannot tell it from 2^53
  TestVolume v = box({4, 4, 4}, 0.0);
  test::writeTestNrrd(file("i64.nrrd"), v, "int64", bytesOf(signedLabels), false);
  const VolumeLoad all = loadVolume(file("i64.nrrd"));
  EXPECT_EQ(all.labels,
            (std::vector<std::uint64_t>{0, std::uint64_t(big), std::uint64_t(big) + 1}));
  EXPECT_EQ(all.grid.countVoxels(kFillHalf), 9u);
  VolumeOptions odd;
  odd.label = std::uint64_t(big) + 1;
  EXPECT_EQ(loadVolume(file("i64.nrrd"), odd).grid.countVoxels(kFillHalf), 1u);
  odd.label = std::uint64_t(big);
  EXPECT_EQ(loadVolume(file("i64.nrrd"), odd).grid.countVoxels(kFillHalf), 8u);

  const std::uint64_t top = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint64_t> unsignedLabels(64, 0);
  for (int i = 30; i < 35; ++i) unsignedLabels[std::size_t(i)] = top;
  unsignedLabels[50] = top - 1;
  test::writeTestNrrd(file("u64.nrrd"), v, "uint64", bytesOf(unsignedLabels), true);
  test::writeTestNifti(file("u64.nii"), v, 1280, 64, bytesOf(unsignedLabels), false);
  for (const char* name : {"u64.nrrd", "u64.nii"}) {
    SCOPED_TRACE(name);
    VolumeOptions topLabel;
    topLabel.label = top;
    const VolumeLoad load = loadVolume(file(name), topLabel);
    EXPECT_EQ(load.labels, (std::vector<std::uint64_t>{0, top - 1, top}));
    EXPECT_EQ(load.grid.countVoxels(kFillHalf), 5u);
  }
}

TEST_F(VolumeValues, AxesStoredInAnotherOrderAreReordered) {
  // Stored 4 x 6 x 8, stored axis 0 along P (y), axis 1 along L (x): placed 6 x 4 x 8.
  TestVolume v = box({4, 6, 8}, 0.0);
  for (double& x : v.values) x = 1.0;
  v.values[at(v, 0, 0, 0)] = 0.0;
  v.values[at(v, 1, 2, 3)] = 2.0;
  const std::string bytes = test::encodeAs<std::uint8_t>(v.values);
  test::writeTestNrrd(file("perm.nrrd"), v, "uint8", bytes, false, "",
                      "(0,0.5,0) (0.5,0,0) (0,0,0.5)");
  // The same in NIfTI: sform rows in RAS (LPS x and y negated).
  test::writeTestNifti(file("perm.nii"), v, 2, 8, bytes, false);
  std::string nii = test::readBytes(file("perm.nii"));
  const float srow[3][4] = {{0, -0.5f, 0, -10.25f}, {-0.5f, 0, 0, 4.75f}, {0, 0, 0.5f, 3.25f}};
  std::memcpy(&nii[280], srow, sizeof srow);
  test::writeBytes(file("perm.nii"), nii);
  VolumeOptions two;
  two.label = 2;
  for (const char* name : {"perm.nrrd", "perm.nii"}) {
    SCOPED_TRACE(name);
    const VolumeLoad load = loadVolume(file(name), two);
    EXPECT_EQ(load.grid.dims(), glm::ivec3(6, 4, 8));
    EXPECT_EQ(load.grid.fill({2, 1, 3}), kFillFull);
    EXPECT_EQ(load.grid.countVoxels(kFillHalf), 1u);
    EXPECT_NEAR(load.grid.originMm().x, 10.0, 1e-5);
    EXPECT_NEAR(load.grid.originMm().y, -5.0, 1e-5);
  }
  // Stored axis 1 also runs backwards (towards R): its index mirrors.
  test::writeTestNrrd(file("permflip.nrrd"), v, "uint8", bytes, false, "",
                      "(0,0.5,0) (-0.5,0,0) (0,0,0.5)");
  const VolumeLoad flipped = loadVolume(file("permflip.nrrd"), two);
  EXPECT_EQ(flipped.grid.fill({3, 1, 3}), kFillFull);
  EXPECT_NEAR(flipped.grid.originMm().x, 10.25 - 2.5 - 0.25, 1e-5);
  // Two axes along one direction are no grid.
  test::writeTestNrrd(file("degenerate.nrrd"), v, "uint8", bytes, false, "",
                      "(0,0.5,0) (0,0.5,0) (0,0,0.5)");
  EXPECT_NE(refusal("degenerate.nrrd").find("both run along P"), std::string::npos)
      << refusal("degenerate.nrrd");
}

TEST_F(VolumeValues, NiftiHeadersThatDisagreeWithThemselvesAreRefusedSayingHow) {
  TestVolume v = box({4, 4, 4}, 0.0);
  v.values[21] = 1.0;
  const std::string bytes = test::encodeAs<std::uint8_t>(v.values);
  const auto patched = [&](const std::string& name, std::size_t offset, const auto value) {
    test::writeTestNifti(file(name), v, 2, 8, bytes, false);
    std::string nii = test::readBytes(file(name));
    std::memcpy(&nii[offset], &value, sizeof value);
    test::writeBytes(file(name), nii);
  };
  patched("bitpix.nii", 72, std::int16_t(16));
  EXPECT_NE(refusal("bitpix.nii").find("bitpix 16 does not match datatype 2 (uint8, 8 bits)"),
            std::string::npos);
  patched("dim0.nii", 40, std::int16_t(8));
  EXPECT_NE(refusal("dim0.nii").find("dim[0] = 8 is not a number of dimensions (1 to 7)"),
            std::string::npos);
  patched("sform.nii", 280 + 12, std::numeric_limits<float>::quiet_NaN());
  EXPECT_NE(refusal("sform.nii").find("the sform is not finite"), std::string::npos)
      << refusal("sform.nii");
  EXPECT_EQ(refusal("sform.nii").find("mm"), std::string::npos) << refusal("sform.nii");
  // The qform: a unit quaternion's b, c, d square-sum to at most 1.
  test::writeTestNifti(file("q.nii"), v, 2, 8, bytes, false);
  std::string q = test::readBytes(file("q.nii"));
  const std::int16_t qform = 1, sform = 0;
  std::memcpy(&q[252], &qform, 2);
  std::memcpy(&q[254], &sform, 2);
  const float bcd[3] = {0.0f, 0.0f, 1.0f};  // 180 degrees about z: RAS x, y negated = LPS as is
  std::memcpy(&q[256], bcd, sizeof bcd);
  test::writeBytes(file("q.nii"), q);
  EXPECT_EQ(loadVolume(file("q.nii")).grid.countVoxels(kFillHalf), 1u);
  const float bad[3] = {0.6f, 0.6f, 0.6f};
  std::memcpy(&q[256], bad, sizeof bad);
  test::writeBytes(file("qbad.nii"), q);
  EXPECT_NE(refusal("qbad.nii")
                .find("the qform quaternion (b, c, d) = (0.6, 0.6, 0.6) is invalid: b^2 + c^2 + "
                      "d^2 = 1.08"),
            std::string::npos)
      << refusal("qbad.nii");
}

TEST_F(VolumeValues, AnIsoLevelThatIsNotFiniteIsRefusedBeforeReading) {
  for (const double iso :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()}) {
    VolumeOptions o;
    o.isoValue = iso;
    const std::string m = refusal("missing.nrrd", o);  // the file is not even read
    EXPECT_EQ(m.rfind("volume.isoValue ", 0), 0u) << m;
    EXPECT_NE(m.find("must be a finite number"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace osteon::geometry
