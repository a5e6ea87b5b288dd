// MetaImage (.mha, .mhd) through osteon's volume loader (geometry/src/io/metaimage_io.cpp):
// attached and detached data, raw and zlib, byte order, element types, and where the
// geometry keys put the voxels in LPS.
#include <cstring>
#include <filesystem>
#include <string>
#include <zlib.h>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

class MetaImage : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("metaimage");
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return dir_ + "/" + name; }

  std::string refusal(const std::string& path, bool allowOutsideData = false) {
    VolumeOptions options;
    options.allowOutsideData = allowOutsideData;
    try {
      readRawVolume(path, options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(read)";
  }
};

// 2 x 3 x 4 int16 values 10 * index - 50, little-endian.
std::string int16Bytes(bool bigEndian = false) {
  std::string bytes;
  for (int i = 0; i < 24; ++i) {
    const std::int16_t v = std::int16_t(10 * i - 50);
    char b[2];
    std::memcpy(b, &v, 2);
    if (bigEndian) std::swap(b[0], b[1]);
    bytes.append(b, 2);
  }
  return bytes;
}

std::string header(const std::string& extra, const std::string& dataFile,
                   const std::string& type = "MET_SHORT") {
  return "ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 2 3 4\n"
         "ElementSpacing = 0.5 0.5 0.5\nOffset = 10 20 30\n" +
         extra + "ElementType = " + type + "\nElementDataFile = " + dataFile + "\n";
}

double valueAt(const RawVolume& v, int x, int y, int z) {
  const std::size_t i = std::size_t(x + v.sizes.x * (y + v.sizes.y * z));
  return v.visit([&](auto values) { return double(values[i]); });
}

void expectIdentityLayout(const RawVolume& v) {
  ASSERT_EQ(v.sizes, glm::ivec3(2, 3, 4));
  EXPECT_EQ(v.type, "int16");
  EXPECT_DOUBLE_EQ(v.voxelSizeMm, 0.5);
  EXPECT_NEAR(v.originMm.x, 9.75, 1e-12);
  EXPECT_NEAR(v.originMm.z, 29.75, 1e-12);
  for (int i = 0; i < 24; ++i) EXPECT_EQ(valueAt(v, i % 2, i / 2 % 3, i / 6), 10 * i - 50);
}

TEST_F(MetaImage, AttachedDetachedCompressedAndBigEndianReadAlike) {
  test::writeBytes(file("a.mha"), header("", "LOCAL") + int16Bytes());
  expectIdentityLayout(readRawVolume(file("a.mha"), VolumeOptions{}));
  EXPECT_EQ(volumeFormat(file("a.mha")), "metaimage");
  EXPECT_TRUE(isVolumePath(file("A.MHD")));

  test::writeBytes(file("d.raw"), int16Bytes(true));
  test::writeBytes(file("d.mhd"), header("BinaryDataByteOrderMSB = True\n", "d.raw"));
  expectIdentityLayout(readRawVolume(file("d.mhd"), VolumeOptions{}));

  const std::string raw = int16Bytes();
  uLongf size = compressBound(uLong(raw.size()));
  std::string packed(size, '\0');
  ASSERT_EQ(compress(reinterpret_cast<Bytef*>(&packed[0]), &size,
                     reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size())),
            Z_OK);
  packed.resize(size);
  test::writeBytes(
      file("z.mha"),
      header("CompressedData = True\nCompressedDataSize = " + std::to_string(size) + "\n",
             "LOCAL") +
          packed);
  expectIdentityLayout(readRawVolume(file("z.mha"), VolumeOptions{}));
}

TEST_F(MetaImage, ElementTypesMapToOsteonTypes) {
  const std::pair<const char*, const char*> types[] = {
      {"MET_UCHAR", "uint8"}, {"MET_CHAR", "int8"},    {"MET_USHORT", "uint16"},
      {"MET_INT", "int32"},   {"MET_UINT", "uint32"},  {"MET_LONG_LONG", "int64"},
      {"MET_FLOAT", "float"}, {"MET_DOUBLE", "double"}};
  for (const auto& [met, type] : types) {
    const std::size_t bytes =
        std::string(type).find("64") != std::string::npos || std::string(type) == "double"  ? 8
        : std::string(type).find("32") != std::string::npos || std::string(type) == "float" ? 4
        : std::string(type).find("16") != std::string::npos                                 ? 2
                                                                                            : 1;
    test::writeBytes(file("t.mha"), header("", "LOCAL", met) + std::string(24 * bytes, '\0'));
    EXPECT_EQ(readRawVolume(file("t.mha"), VolumeOptions{}).type, type) << met;
  }
}

TEST_F(MetaImage, TransformMatrixAndOrientationPlaceTheVoxelsInLps) {
  // Axis 2 runs towards inferior (-S): the volume is flipped along z on loading.
  test::writeBytes(file("m.mha"),
                   header("TransformMatrix = 1 0 0 0 1 0 0 0 -1\n", "LOCAL") + int16Bytes());
  const RawVolume m = readRawVolume(file("m.mha"), VolumeOptions{});
  EXPECT_NEAR(m.originMm.z, 30.0 - 3 * 0.5 - 0.25, 1e-12);
  EXPECT_EQ(valueAt(m, 0, 0, 3), -50);  // stored slice 0 is the top one
  // RAS as ITK writes it: x from right (+L), y from anterior (+P), z from superior (-S).
  test::writeBytes(file("o.mha"), header("AnatomicalOrientation = RAS\n", "LOCAL") + int16Bytes());
  const RawVolume o = readRawVolume(file("o.mha"), VolumeOptions{});
  EXPECT_EQ(valueAt(o, 0, 0, 3), -50);
  EXPECT_EQ(valueAt(o, 1, 0, 3), -40);
  test::writeBytes(file("i.mha"), header("AnatomicalOrientation = RAI\n", "LOCAL") + int16Bytes());
  expectIdentityLayout(readRawVolume(file("i.mha"), VolumeOptions{}));
}

TEST_F(MetaImage, BadHeadersAndDataFilesAreRefused) {
  test::writeBytes(file("missing.mhd"), header("", "nowhere.raw"));
  EXPECT_NE(refusal(file("missing.mhd")).find("nowhere.raw"), std::string::npos);
  test::writeBytes(file("list.mhd"), header("", "LIST"));
  EXPECT_NE(refusal(file("list.mhd")).find("LIST"), std::string::npos);
  fs::create_directories(file("sub"));
  test::writeBytes(file("outside.raw"), int16Bytes());
  test::writeBytes(file("sub/out.mhd"), header("", "../outside.raw"));
  EXPECT_NE(refusal(file("sub/out.mhd")).find("volume.allowOutsideData"), std::string::npos);
  expectIdentityLayout(readRawVolume(file("sub/out.mhd"), [] {
    VolumeOptions o;
    o.allowOutsideData = true;
    return o;
  }()));
  test::writeBytes(file("short.mha"), header("", "LOCAL") + int16Bytes().substr(4));
  EXPECT_NE(refusal(file("short.mha")).find("truncated"), std::string::npos);
  test::writeBytes(file("type.mha"), header("", "LOCAL", "MET_STRING") + int16Bytes());
  EXPECT_NE(refusal(file("type.mha")).find("ElementType 'MET_STRING'"), std::string::npos)
      << refusal(file("type.mha"));
  test::writeBytes(file("dims.mha"),
                   "NDims = 2\nDimSize = 2 3\nElementType = MET_SHORT\n"
                   "ElementDataFile = LOCAL\n");
  EXPECT_EQ(refusal(file("dims.mha")), file("dims.mha") + ": NDims 2 is not supported (need 3)");
  test::writeBytes(file("none.mha"), "just text\n");
  EXPECT_NE(refusal(file("none.mha")).find("not 'Key = Value'"), std::string::npos);
}

}  // namespace
}  // namespace osteon::geometry
