// DICOM CT series through osteon's volume loader (geometry/src/io/dicom_volume.cpp and the
// GDCM plugin, geometry/plugin): series written with GDCM here, plain and compressed, with
// shuffled file names; HU after rescale, slice order, the series picked, the refusals.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "io/volume_readers.h"
#include "osteon/core/error.h"
#include "osteon/geometry/io/dicom_series.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/dicom_series.h"
#include "support/files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

class DicomVolume : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("dicom");
  void TearDown() override { fs::remove_all(dir_); }

  // Writes the slices into `folder` under shuffled names (fixed seed), so that name order is
  // not slice order.
  std::string writeSeries(const std::string& folder, const std::vector<test::DicomSlice>& slices,
                          unsigned seed = 7) {
    const std::string path = dir_ + "/" + folder;
    fs::create_directories(path);
    std::vector<int> names(slices.size());
    for (std::size_t i = 0; i < names.size(); ++i) names[i] = int(i);
    std::mt19937 random(seed);
    std::shuffle(names.begin(), names.end(), random);
    for (std::size_t k = 0; k < slices.size(); ++k) {
      test::writeDicomSlice(path + "/IM" + std::to_string(1000 + names[k]) + ".dcm", slices[k]);
    }
    return path;
  }

  std::string refusal(const std::string& path, const std::string& series = "") {
    VolumeOptions options;
    options.series = series;
    try {
      readRawVolume(path, options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(read)";
  }
};

// The HU of voxel (x, y, z) of a placed volume.
double hu(const RawVolume& v, int x, int y, int z) {
  const std::size_t i =
      std::size_t(x) +
      std::size_t(v.sizes.x) * (std::size_t(y) + std::size_t(v.sizes.y) * std::size_t(z));
  return v.visit([&](auto values) { return double(values[i]) * v.slope + v.intercept; });
}

void expectStack(const RawVolume& v, int count, int columns = 4, int rows = 3) {
  ASSERT_EQ(v.sizes, glm::ivec3(columns, rows, count));
  for (int z = 0; z < count; ++z) {
    for (int y = 0; y < rows; ++y) {
      for (int x = 0; x < columns; ++x) {
        // dicomStack's stored 100 k + i - 1024, with slope 2 and intercept -24 where set.
        const double stored = 100.0 * z + (x + columns * y) - 1024;
        ASSERT_EQ(hu(v, x, y, z), stored * 2.0 - 24.0) << x << " " << y << " " << z;
      }
    }
  }
}

std::vector<test::DicomSlice> rescaled(int count, int columns = 4, int rows = 3) {
  std::vector<test::DicomSlice> slices = test::dicomStack(count, -40.0, 1.0, columns, rows);
  for (test::DicomSlice& s : slices) {
    s.slope = 2.0;
    s.intercept = -24.0;
  }
  return slices;
}

TEST_F(DicomVolume, PlainSeriesIsSortedByPositionAndRescaledToHu) {
  const std::string folder = writeSeries("plain", rescaled(6));
  const RawVolume v = readRawVolume(folder, VolumeOptions{});
  EXPECT_EQ(v.type, "int16");
  EXPECT_FALSE(v.integer);  // rescaled: the values are HU, not the stored integers
  EXPECT_DOUBLE_EQ(v.slope, 2.0);
  EXPECT_DOUBLE_EQ(v.intercept, -24.0);
  expectStack(v, 6);
  EXPECT_NEAR(v.originMm.z, -40.5, 1e-9);
  EXPECT_NEAR(v.originMm.x, -0.5, 1e-9);
  EXPECT_EQ(volumeFormat(folder), "dicom");
  EXPECT_TRUE(isVolumePath(folder));
}

TEST_F(DicomVolume, OneSliceFileStandsForItsSeries) {
  const std::string folder = writeSeries("single", rescaled(5));
  const RawVolume v = readRawVolume(folder + "/IM1002.dcm", VolumeOptions{});
  expectStack(v, 5);
}

TEST_F(DicomVolume, CompressedSeriesDecodeToTheSameHu) {
  // 40 x 30 pixels: GDCM's JPEG 2000 encoder overruns its buffer for images of a few pixels.
  for (const char* syntax : {"jpeglossless", "jpegls", "jpeg2000", "rle"}) {
    SCOPED_TRACE(syntax);
    std::vector<test::DicomSlice> slices = rescaled(4, 40, 30);
    for (test::DicomSlice& s : slices) s.transferSyntax = syntax;
    const std::string folder = writeSeries(syntax, slices);
    expectStack(readRawVolume(folder, VolumeOptions{}), 4, 40, 30);
  }
}

TEST_F(DicomVolume, JpegBaselineEightBitDecodesWithinItsLoss) {
  std::vector<test::DicomSlice> slices = test::dicomStack(3, 0.0, 1.0);
  for (std::size_t k = 0; k < slices.size(); ++k) {
    for (std::size_t i = 0; i < slices[k].stored.size(); ++i)
      slices[k].stored[i] = std::int32_t(60 * k + 10 + 4 * i);
    slices[k].eightBit = true;
    slices[k].transferSyntax = "jpegbaseline";
  }
  const RawVolume v = readRawVolume(writeSeries("baseline", slices), VolumeOptions{});
  ASSERT_EQ(v.type, "uint8");
  for (int z = 0; z < 3; ++z) {
    for (int i = 0; i < 12; ++i) EXPECT_NEAR(hu(v, i % 4, i / 4, z), 60 * z + 10 + 4 * i, 12.0);
  }
}

TEST_F(DicomVolume, SlicesWithTheirOwnRescaleBecomeFloatHu) {
  std::vector<test::DicomSlice> slices = rescaled(4);
  for (std::size_t k = 0; k < slices.size(); ++k) {
    // The same HU from another slope and intercept in every other slice.
    if (k % 2 == 1) {
      for (std::int32_t& s : slices[k].stored) s = s * 2 - 24 + 1000;
      slices[k].slope = 1.0;
      slices[k].intercept = -1000.0;
    }
  }
  const RawVolume v = readRawVolume(writeSeries("own", slices), VolumeOptions{});
  EXPECT_EQ(v.type, "float");
  expectStack(v, 4);
}

TEST_F(DicomVolume, TheLargestSeriesUnlessOneIsNamed) {
  std::vector<test::DicomSlice> big = rescaled(5), small = rescaled(3);
  for (test::DicomSlice& s : small) s.seriesUid = "1.2.3.4.5";
  const std::string folder = writeSeries("two", big);
  for (std::size_t k = 0; k < small.size(); ++k)
    test::writeDicomSlice(folder + "/S" + std::to_string(k) + ".dcm", small[k]);
  EXPECT_EQ(readRawVolume(folder, VolumeOptions{}).sizes.z, 5);
  VolumeOptions named;
  named.series = "1.2.3.4.5";
  EXPECT_EQ(readRawVolume(folder, named).sizes.z, 3);
  const std::string wrong = refusal(folder, "9.9");
  EXPECT_NE(wrong.find(folder + ": volume.series 9.9 is not among its series: "), std::string::npos)
      << wrong;
  EXPECT_NE(wrong.find("1.2.3.4.5 (3 slices)"), std::string::npos) << wrong;
  const std::vector<DicomSeries> listed = listDicomSeries(folder);
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_EQ(listed[1].uid, "1.2.826.0.1.3680043.2.1125.1");
  EXPECT_EQ(listed[1].slices, 5);
  EXPECT_EQ(defaultDicomSeries(listed), 1);
}

TEST_F(DicomVolume, TiedSeriesAreRefusedWithTheirUids) {
  std::vector<test::DicomSlice> a = rescaled(3), b = rescaled(3);
  for (test::DicomSlice& s : b) s.seriesUid = "1.2.3.4.6";
  const std::string folder = writeSeries("tie", a);
  for (std::size_t k = 0; k < b.size(); ++k)
    test::writeDicomSlice(folder + "/B" + std::to_string(k) + ".dcm", b[k]);
  const std::string message = refusal(folder);
  EXPECT_NE(message.find("mixed series): give volume.series UID"), std::string::npos) << message;
  EXPECT_NE(message.find("1.2.3.4.6 (3 slices)"), std::string::npos) << message;
}

TEST_F(DicomVolume, MissingAndUnevenSlicesAreRefusedNamingTheGap) {
  std::vector<test::DicomSlice> slices = rescaled(6);
  slices.erase(slices.begin() + 3);
  const std::string folder = writeSeries("missing", slices);
  const std::string message = refusal(folder);
  EXPECT_NE(message.find(folder + ": a gap of 2 mm between slices"), std::string::npos) << message;
  EXPECT_NE(message.find("at -38 and -36 mm along the slice normal"), std::string::npos) << message;
  EXPECT_NE(message.find("1 slice missing"), std::string::npos) << message;

  std::vector<test::DicomSlice> uneven = rescaled(5);
  uneven[4].position[2] += 0.5;
  const std::string unevenMessage = refusal(writeSeries("uneven", uneven));
  EXPECT_NE(unevenMessage.find("unevenly spaced slices"), std::string::npos) << unevenMessage;
}

TEST_F(DicomVolume, ObliqueAndTiltedSeriesGiveTheirFullGeometry) {
  std::vector<test::DicomSlice> slices = rescaled(4);
  const double a = 15.0 * M_PI / 180.0;
  for (std::size_t k = 0; k < slices.size(); ++k) {
    test::DicomSlice& s = slices[k];
    const double o[6] = {std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0};
    std::copy(o, o + 6, s.orientation);
    s.pixelSpacing[0] = 0.5;   // between rows
    s.pixelSpacing[1] = 0.75;  // between columns
    s.position[0] = 3.0;
    s.position[1] = 0.25 * double(k);  // a tilted gantry: slices slide along y
    s.position[2] = 2.0 * double(k);
  }
  const io::StoredVolume v = io::readDicom(writeSeries("oblique", slices), "");
  EXPECT_NEAR(v.m[0][0], 0.75 * std::cos(a), 1e-6);
  EXPECT_NEAR(v.m[1][0], 0.75 * std::sin(a), 1e-6);
  EXPECT_NEAR(v.m[0][1], -0.5 * std::sin(a), 1e-6);
  EXPECT_NEAR(v.m[1][1], 0.5 * std::cos(a), 1e-6);
  EXPECT_NEAR(v.m[1][2], 0.25, 1e-6);
  EXPECT_NEAR(v.m[2][2], 2.0, 1e-6);
  EXPECT_NEAR(v.centre0.x, 3.0, 1e-9);
  EXPECT_EQ(v.volume.sizes, glm::ivec3(4, 3, 4));
}

TEST_F(DicomVolume, AMultiFrameFileKeepsItsGeometry) {
  test::DicomSlice s = test::dicomStack(1, 0.0, 1.0).front();
  const double a = 15.0 * M_PI / 180.0;
  const double o[6] = {std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0};
  std::copy(o, o + 6, s.orientation);
  s.pixelSpacing[0] = 0.5;
  s.pixelSpacing[1] = 0.75;
  s.position[0] = 1.0;
  s.position[1] = 2.0;
  s.position[2] = 3.0;
  fs::create_directories(dir_ + "/multi");
  test::writeDicomMultiFrame(dir_ + "/multi/ct.dcm", s, 5, 2.0);
  const io::StoredVolume v = io::readDicom(dir_ + "/multi/ct.dcm", "");
  EXPECT_EQ(v.volume.sizes, glm::ivec3(4, 3, 5));
  EXPECT_NEAR(v.m[0][0], 0.75 * std::cos(a), 1e-6);
  EXPECT_NEAR(v.m[1][1], 0.5 * std::cos(a), 1e-6);
  EXPECT_NEAR(v.m[2][2], 2.0, 1e-6);
  EXPECT_NEAR(v.centre0.x, 1.0, 1e-9);
  EXPECT_NEAR(v.centre0.z, 3.0, 1e-9);
  v.volume.visit([&](auto values) {
    for (int k = 0; k < 5; ++k)
      EXPECT_EQ(double(values[std::size_t(12 * k + 5)]), 100 * k + 5 - 1024);
  });
}

TEST_F(DicomVolume, OtherImagesAndBrokenFilesAreRefused) {
  std::vector<test::DicomSlice> mr = rescaled(3);
  for (test::DicomSlice& s : mr) s.sopClass = "1.2.840.10008.5.1.4.1.1.4";
  const std::string notCt = refusal(writeSeries("mr", mr));
  EXPECT_NE(notCt.find("not CT image storage"), std::string::npos) << notCt;

  const std::string folder = writeSeries("truncated", rescaled(3));
  const std::string victim = folder + "/IM1001.dcm";
  const std::string bytes = test::readBytes(victim);
  test::writeBytes(victim, bytes.substr(0, bytes.size() - 10));
  const std::string message = refusal(folder);
  EXPECT_NE(message.find(folder + ": IM1001.dcm: "), std::string::npos) << message;

  const std::string empty = dir_ + "/empty";
  fs::create_directories(empty);
  test::writeBytes(empty + "/notes.txt", "not DICOM");
  EXPECT_EQ(refusal(empty), empty + ": no DICOM file in the folder");
  EXPECT_EQ(refusal(dir_ + "/missing.dcm").rfind(dir_ + "/missing.dcm: ", 0), 0u);
}

}  // namespace
}  // namespace osteon::geometry
