// The NRRD header as every NRRD osteon opens reads it (geometry/src/io/nrrd_header.cpp):
// fields given once, spatial kinds only, line and byte skips honoured, osteon's own grid known
// by all it writes, data files kept in the header's folder and measured before they are read.
#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"
#include "support/shapes.h"
#include "support/volume_files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

// A 4^3 uint8 label map: a 2^3 cube of label 1 in the middle, 0 around it.
std::string cubeBytes() {
  std::string bytes(64, '\0');
  for (int z = 1; z < 3; ++z) {
    for (int y = 1; y < 3; ++y) {
      for (int x = 1; x < 3; ++x) bytes[std::size_t((z * 4 + y) * 4 + x)] = 1;
    }
  }
  return bytes;
}

std::string header(const std::string& extra, const std::string& encoding = "raw",
                   const std::string& kinds = "domain domain domain") {
  return "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nspacings: 1 1 1\nkinds: " + kinds +
         "\nencoding: " + encoding + "\n" + extra;
}

class NrrdHeader : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("nrrd_header");
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return dir_ + "/" + name; }

  // Loads `path` as a volume and checks it is the cube label map.
  void expectCube(const std::string& path, const VolumeOptions& options = {}) const {
    SCOPED_TRACE(path);
    try {
      const VolumeLoad load = loadVolume(path, options);
      EXPECT_EQ(load.kind, "label map");
      EXPECT_EQ(load.grid.dims(), glm::ivec3(4));
      EXPECT_EQ(load.grid.countVoxels(kFillHalf), 8u);
      EXPECT_EQ(load.grid.fill({1, 1, 1}), kFillFull);
      EXPECT_EQ(load.grid.fill({0, 0, 0}), 0);
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }

  // Loading fails with one line naming `named` (default: the file) and `reason`.
  static void expectRefused(const std::string& path, const std::string& reason,
                            const std::string& named = "", const VolumeOptions& options = {}) {
    SCOPED_TRACE(path + ": " + reason);
    try {
      loadVolume(path, options);
      ADD_FAILURE() << "loaded";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path, 0), 0u) << what;
      EXPECT_NE(what.find(named.empty() ? path : named), std::string::npos) << what;
      EXPECT_NE(what.find(reason), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
};

// Two `sizes:` lines once turned 20x20x20 into 1x1x8000: the last one won.
TEST_F(NrrdHeader, FieldsGivenTwiceAreRefused) {
  const std::string p = file("twice.nrrd");
  test::writeBytes(p, header("sizes: 1 1 64\n\n") + cubeBytes());
  expectRefused(p, "field 'sizes' given twice (header lines 4 and 8)");
  test::writeBytes(p, header("data file: a.raw\ndatafile: b.raw\n"));
  expectRefused(p, "field 'datafile' given twice");
  test::writeBytes(p, header("spacings: 2 2 2\n\n") + cubeBytes());
  expectRefused(p, "field 'spacings' given twice");
  test::writeBytes(p, header("a:=1\na:=2\n\n") + cubeBytes());
  expectRefused(p, "key 'a' given twice");
  // osteon's own grids are read by the same reader.
  VoxelGrid grid({4, 4, 4}, glm::dvec3(0.0), 1.0);
  writeNrrd(grid, p, false);
  std::string bytes = test::readBytes(p);
  bytes.insert(bytes.find("sizes:"), "sizes: 1 1 64\n");
  test::writeBytes(p, bytes);
  try {
    readNrrd(p);
    ADD_FAILURE() << "loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'sizes' given twice"), std::string::npos)
        << e.what();
  }
}

TEST_F(NrrdHeader, OnlySpatialKindsAreAxes) {
  const std::string p = file("kinds.nrrd");
  for (const char* kinds : {"RGB-color domain domain", "domain vector domain", "domain domain list",
                            "time domain domain", "3-color space space"}) {
    test::writeBytes(p, header("\n", "raw", kinds) + cubeBytes());
    expectRefused(p, "not a spatial axis");
  }
  test::writeBytes(p,
                   "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 4 4\nspacings: 1 1 1\n"
                   "kinds: RGB-color domain domain\nencoding: raw\n\n" +
                       std::string(48, '\0'));
  expectRefused(p, "axis 0 is 'RGB-color', not a spatial axis");
  test::writeBytes(p, header("\n", "raw", "domain domain") + cubeBytes());
  expectRefused(p, "are not three");
  test::writeBytes(p, header("\n", "raw", "space ??? Domain") + cubeBytes());
  expectCube(p);
}

TEST_F(NrrdHeader, LineAndByteSkipsAreHonoured) {
  const std::string cube = cubeBytes();
  // Attached: lines, then bytes, after the header's blank line.
  test::writeBytes(file("a.nrrd"),
                   header("line skip: 2\nbyte skip: 3\n\n") + "one\ntwo\nxyz" + cube);
  expectCube(file("a.nrrd"));
  // Detached: from the data file's start.
  test::writeBytes(file("d.nhdr"), header("data file: d.raw\nline skip: 1\nbyte skip: 5\n"));
  test::writeBytes(file("d.raw"), "text header of another tool\n12345" + cube);
  expectCube(file("d.nhdr"));
  // byte skip -1: the data is the file's last bytes.
  test::writeBytes(file("end.nhdr"), header("data file: end.raw\nbyte skip: -1\n"));
  test::writeBytes(file("end.raw"), std::string(1000, 'x') + cube);
  expectCube(file("end.nhdr"));
  // gzip: lines of the file, bytes of the inflated stream.
  test::writeBytes(file("gz.nrrd"), header("line skip: 1\nbyte skip: 7\n\n", "gzip") +
                                        "junk line\n" + test::gzipBytes("1234567" + cube));
  expectCube(file("gz.nrrd"));
  // osteon's own grids too.
  VoxelGrid grid({4, 4, 4}, glm::dvec3(0.0), 1.0);
  grid.set({1, 2, 3}, kFillFull, 0);
  writeNrrd(grid, file("g.nrrd"), false);
  std::string bytes = test::readBytes(file("g.nrrd"));
  const std::size_t data = bytes.find("\n\n") + 2;
  bytes.insert(data, "two\nlines\n");
  bytes.insert(bytes.find("encoding:"), "line skip: 2\n");
  test::writeBytes(file("g.nrrd"), bytes);
  EXPECT_EQ(readNrrd(file("g.nrrd")).grid.fill({1, 2, 3}), kFillFull);

  const struct {
    std::string bytes;
    std::string reason;
  } refused[] = {
      {header("byte skip: -2\n\n") + cube, "byte skip '-2' is not a whole number"},
      {header("line skip: x\n\n") + cube, "line skip 'x' is not a whole number"},
      {header("line skip: 3\n\n") + "a\n" + cube, "line skip 3 runs past the end of the file"},
      {header("byte skip: 65\n\n") + cube, "byte skip 65 passes the end of the file"},
      {header("byte skip: 1\n\n") + cube,
       "truncated: 63 bytes of data after the line and byte skips"},
      {header("byte skip: -1\n\n", "gzip") + test::gzipBytes(cube), "byte skip -1"},
      {header("byte skip: 1\n\n", "gzip") + test::gzipBytes(cube), "truncated"},
  };
  for (const auto& c : refused) {
    test::writeBytes(file("bad.nrrd"), c.bytes);
    expectRefused(file("bad.nrrd"), c.reason);
  }
}

// A user's label map with a key of its own that happens to start with osteon_ is a label map.
TEST_F(NrrdHeader, OsteonGridOnlyByAllItWrites) {
  const std::string cube = cubeBytes();
  for (const char* extra : {"osteon_foo:=1\n", "osteon_voxel_size_mm:=1\n",
                            "osteon_voxel_size_mm:=1\nosteon_origin_mm:=-0.5 -0.5 -0.5\n",
                            "# osteon voxel grid: fill, 0 empty .. 255 full\nosteon_foo:=1\n"}) {
    test::writeBytes(file("labels.nrrd"), header(std::string(extra) + "\n") + cube);
    expectCube(file("labels.nrrd"));
  }
  VoxelGrid grid({4, 4, 4}, glm::dvec3(0.0), 1.0);
  grid.set({1, 1, 1}, Fill(kFillPerStep * 3), 7);
  writeNrrd(grid, file("g.nrrd"));
  const VolumeLoad load = loadVolume(file("g.nrrd"));
  EXPECT_EQ(load.kind, "osteon grid");
  EXPECT_EQ(load.grid.fill({1, 1, 1}), Fill(kFillPerStep * 3));
  expectRefused(densityPathFor(file("g.nrrd")), "an osteon density file");
}

TEST_F(NrrdHeader, DataFilesStayInTheHeadersFolder) {
  const std::string cube = cubeBytes();
  fs::create_directories(file("in/sub"));
  test::writeBytes(file("outside.raw"), cube);
  test::writeBytes(file("in/sub/inside.raw"), cube);
  fs::create_symlink(file("outside.raw"), file("in/link.raw"));
  const struct {
    std::string dataFile;
    std::string resolved;  // what the message says it resolves to
  } outside[] = {
      {"../outside.raw", "outside.raw"},
      {"sub/../../outside.raw", "outside.raw"},
      {"link.raw", "outside.raw"},  // a symlink in the folder to a file outside it
      {file("outside.raw"), "outside.raw"},
  };
  VolumeOptions allow;
  allow.allowOutsideData = true;
  for (const auto& c : outside) {
    test::writeBytes(file("in/h.nhdr"), header("data file: " + c.dataFile + "\n"));
    expectRefused(file("in/h.nhdr"), "is outside the header's folder", c.dataFile);
    expectRefused(file("in/h.nhdr"), "give volume.allowOutsideData to read it", c.resolved);
    expectCube(file("in/h.nhdr"), allow);
  }
  for (const char* inside : {"sub/inside.raw", "sub/../sub/inside.raw", "./sub/inside.raw"}) {
    test::writeBytes(file("in/h.nhdr"), header(std::string("data file: ") + inside + "\n"));
    expectCube(file("in/h.nhdr"));
  }
  // /etc/passwd is read as nothing at all, not as a label map of its bytes.
  test::writeBytes(file("in/h.nhdr"), header("data file: ../../../../../../../../etc/passwd\n"));
  expectRefused(file("in/h.nhdr"), "outside the header's folder");
  // Missing files outside are told as outside too: no probing of what exists there.
  test::writeBytes(file("in/h.nhdr"), header("data file: ../nowhere.raw\n"));
  expectRefused(file("in/h.nhdr"), "outside the header's folder");
}

// The format allows blanks in a single data file's name; LIST and numbered patterns are the
// multi-file forms, refused as what they are.
TEST_F(NrrdHeader, DataFileNamesWithBlanksAreOneFile) {
  test::writeBytes(file("my labels 1.raw"), cubeBytes());
  test::writeBytes(file("h.nhdr"), header("data file: my labels 1.raw\n"));
  expectCube(file("h.nhdr"));
  test::writeBytes(file("h.nhdr"), header("data file: LIST\nslice0.raw\n"));
  expectRefused(file("h.nhdr"), "a list of data files (LIST) is not supported");
  test::writeBytes(file("h.nhdr"), header("data file: slice%03d.raw 0 3 1 2\n"));
  expectRefused(file("h.nhdr"), "numbered data files");
  test::writeBytes(file("h.nhdr"), header("data file: my labels 2.raw\n"));
  expectRefused(file("h.nhdr"), "my labels 2.raw: no such file");
  test::writeBytes(file("h.nhdr"),
                   header(std::string("data file: my labels 1.raw\0/../../x.raw\n", 40)));
  expectRefused(file("h.nhdr"), "the file name contains a NUL byte");
  test::writeBytes(file("h.nhdr"), header("data file: my\tlabels.raw\n"));
  expectRefused(file("h.nhdr"), "the name holds a control character");
  test::writeBytes(file("h.nhdr"), header("data file: slice%03d.raw\n"));  // no numbers: one file
  expectRefused(file("h.nhdr"), "slice%03d.raw: no such file");
}

// The data's length is known from the file's size: nothing is read before it is compared.
TEST_F(NrrdHeader, DataLengthIsCheckedBeforeReading) {
  const std::string cube = cubeBytes();
  test::writeBytes(file("h.nhdr"), header("data file: big.raw\n"));
  test::writeBytes(file("big.raw"), cube + "x");
  expectRefused(file("h.nhdr"), "65 bytes of data disagree with sizes, which need 64", "big.raw");
  test::writeBytes(file("big.raw"), cube.substr(1));
  expectRefused(file("h.nhdr"), "truncated: 63 bytes of data, sizes need 64", "big.raw");
  // gzip: inflating stops at the first byte past the sizes; bytes after the stream are refused.
  test::writeBytes(file("gz.nrrd"),
                   header("\n", "gzip") + test::gzipBytes(cube + std::string(100000, '\0')));
  expectRefused(file("gz.nrrd"), "gzip data is longer than the sizes need (64 bytes)");
  test::writeBytes(file("gz.nrrd"), header("\n", "gzip") + test::gzipBytes(cube) + "trailing");
  expectRefused(file("gz.nrrd"), "8 bytes follow the end of the gzip data");
  // Two gzip members, as `cat a.gz b.gz` makes, are one stream.
  test::writeBytes(file("gz.nrrd"), header("\n", "gzip") + test::gzipBytes(cube.substr(0, 20)) +
                                        test::gzipBytes(cube.substr(20)));
  expectCube(file("gz.nrrd"));
}

}  // namespace
}  // namespace osteon::geometry
