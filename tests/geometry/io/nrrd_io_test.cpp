#include "osteon/geometry/io/nrrd_io.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "support/files.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

std::string headerOf(const std::string& path) {
  const std::string bytes = test::readBytes(path);
  const std::size_t end = bytes.find("\n\n");
  return end == std::string::npos ? std::string() : bytes.substr(0, end + 2);
}

// 13 x 9 x 21 (2 x 2 x 3 bricks, every one partial along some axis except the first):
// random bricks, a brick with a single odd voxel, and uniform bricks of several values.
// fillUnit 64: fills on the voxelizer's 1/255 steps (written as uint8); 1: any fill value
// (written as uint16, as after refinement and drilling).
VoxelGrid makeTestGrid(Fill fillUnit = kFillPerStep) {
  VoxelGrid grid({13, 9, 21}, {-12.345678901234567, 3.1, 1e-3}, 0.54);
  std::mt19937 rng(20240607);
  std::uniform_int_distribution<int> fillDist(0, kFillFull / fillUnit);
  std::uniform_int_distribution<int> densityDist(-32768, 32767);
  const Fill uniformFills[] = {0, kFillFull, Fill(128 * fillUnit), Fill(37 * fillUnit)};
  const Density uniformDensities[] = {0, 1200, -7, 32767};
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    const glm::ivec3 lo = grid.brickCoord(brick) * VoxelGrid::kBrickSize;
    const glm::ivec3 hi = glm::min(lo + VoxelGrid::kBrickSize, grid.dims());
    if (brick % 3 == 0) {
      for (int z = lo.z; z < hi.z; ++z)
        for (int y = lo.y; y < hi.y; ++y)
          for (int x = lo.x; x < hi.x; ++x)
            grid.set({x, y, z}, Fill(fillDist(rng) * fillUnit), Density(densityDist(rng)));
    } else if (brick % 5 == 1) {
      grid.setBrickUniform(brick, Fill(200 * fillUnit), 300);
      grid.set(hi - 1, Fill(201 * fillUnit), 300);  // one voxel off: the brick stays allocated
    } else {
      grid.setBrickUniform(brick, uniformFills[brick % 4], uniformDensities[brick % 4]);
    }
  }
  grid.clearDirty();
  return grid;
}

void expectSameVoxels(const VoxelGrid& a, const VoxelGrid& b, bool compareDensity) {
  ASSERT_EQ(a.dims(), b.dims());
  const glm::ivec3 n = a.dims();
  int mismatches = 0;
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        const glm::ivec3 p(x, y, z);
        const Density expected = compareDensity ? a.density(p) : Density(0);
        if (a.fill(p) != b.fill(p) || expected != b.density(p)) ++mismatches;
      }
  EXPECT_EQ(mismatches, 0);
}

TEST(NrrdIo, DensityPathSitsBesideTheFill) {
  EXPECT_EQ(densityPathFor("out/grid.nrrd"), "out/grid.density.nrrd");
  EXPECT_EQ(densityPathFor("grid"), "grid.density.nrrd");
  EXPECT_EQ(densityPathFor("a.b/GRID.NRRD"), "a.b/GRID.density.NRRD");
}

class NrrdRoundTrip : public ::testing::TestWithParam<int> {};

TEST_P(NrrdRoundTrip, IsExact) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("grid.nrrd");
  const VoxelGrid grid = makeTestGrid(Fill(GetParam()));
  EXPECT_NE(headerOf((writeNrrd(grid, path), path))
                .find(GetParam() == kFillPerStep ? "\ntype: uint8\n" : "\ntype: uint16\n"),
            std::string::npos);
  ASSERT_GT(grid.allocatedBrickCount(), 0u);
  ASSERT_LT(grid.allocatedBrickCount(), grid.brickCount());
  writeNrrd(grid, path);
  ASSERT_TRUE(fs::exists(densityPathFor(path)));

  const NrrdReadResult read = readNrrd(path);
  EXPECT_TRUE(read.densityLoaded);
  EXPECT_EQ(read.grid.dims(), grid.dims());
  // Bit-exact, not merely close.
  EXPECT_EQ(read.grid.voxelSizeMm(), grid.voxelSizeMm());
  EXPECT_EQ(read.grid.originMm().x, grid.originMm().x);
  EXPECT_EQ(read.grid.originMm().y, grid.originMm().y);
  EXPECT_EQ(read.grid.originMm().z, grid.originMm().z);
  expectSameVoxels(grid, read.grid, true);
  EXPECT_EQ(read.grid.allocatedBrickCount(), grid.allocatedBrickCount());
  for (std::size_t brick = 0; brick < grid.brickCount(); ++brick) {
    EXPECT_EQ(read.grid.brickAllocated(brick), grid.brickAllocated(brick)) << brick;
  }
  EXPECT_TRUE(read.grid.dirtyBricks().empty());
}

// Fresh voxelizer steps (uint8 on disk) and arbitrary fill units (uint16 on disk).
INSTANTIATE_TEST_SUITE_P(FillUnits, NrrdRoundTrip, ::testing::Values(int(kFillPerStep), 1));

TEST(NrrdIo, FileIsHeaderPlusRawVoxels) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("grid.nrrd");
  const VoxelGrid grid = makeTestGrid();
  writeNrrd(grid, path);
  const std::uint64_t voxels = grid.voxelCount();
  const std::string fillHeader = headerOf(path);
  const std::string densityHeader = headerOf(densityPathFor(path));
  ASSERT_FALSE(fillHeader.empty());
  ASSERT_FALSE(densityHeader.empty());
  EXPECT_EQ(fs::file_size(path), fillHeader.size() + voxels);
  EXPECT_EQ(fs::file_size(densityPathFor(path)), densityHeader.size() + 2 * voxels);

  // x fastest, then y, then z; density little-endian.
  const std::string fillBytes = test::readBytes(path).substr(fillHeader.size());
  const std::string densityBytes =
      test::readBytes(densityPathFor(path)).substr(densityHeader.size());
  const glm::ivec3 n = grid.dims();
  for (const glm::ivec3 p :
       {glm::ivec3(0), glm::ivec3(12, 0, 0), glm::ivec3(3, 8, 0), glm::ivec3(5, 4, 20), n - 1}) {
    const std::size_t i = std::size_t(p.x + n.x * (p.y + n.y * p.z));
    EXPECT_EQ(Fill(static_cast<unsigned char>(fillBytes[i]) * kFillPerStep), grid.fill(p));
    const unsigned lo = static_cast<unsigned char>(densityBytes[2 * i]);
    const unsigned hi = static_cast<unsigned char>(densityBytes[2 * i + 1]);
    EXPECT_EQ(Density(std::uint16_t(lo | (hi << 8))), grid.density(p));
  }
}

TEST(NrrdIo, HeaderIsNrrdWithVoxelCentreOrigin) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("grid.nrrd");
  const VoxelGrid grid = makeTestGrid();
  writeNrrd(grid, path);
  const std::string h = headerOf(path);
  EXPECT_EQ(h.rfind("NRRD0004\n", 0), 0u);
  for (const char* line :
       {"\ntype: uint8\n", "\ndimension: 3\n", "\nspace: left-posterior-superior\n",
        "\nsizes: 13 9 21\n", "\nkinds: domain domain domain\n", "\nendian: little\n",
        "\nencoding: raw\n",
        "\nspace directions: (0.54000000000000004,0,0) "
        "(0,0.54000000000000004,0) "
        "(0,0,0.54000000000000004)\n"}) {
    EXPECT_NE(h.find(line), std::string::npos) << line << "\nin\n" << h;
  }
  EXPECT_NE(headerOf(densityPathFor(path)).find("\ntype: int16\n"), std::string::npos);

  const std::size_t at = h.find("\nspace origin: (");
  ASSERT_NE(at, std::string::npos) << h;
  double x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(h.c_str() + at, "\nspace origin: (%lf,%lf,%lf)", &x, &y, &z), 3);
  const glm::dvec3 centre = grid.originMm() + 0.5 * grid.voxelSizeMm();
  EXPECT_DOUBLE_EQ(x, centre.x);
  EXPECT_DOUBLE_EQ(y, centre.y);
  EXPECT_DOUBLE_EQ(z, centre.z);
  EXPECT_NE(h.find("\nosteon_voxel_size_mm:=0.54000000000000004\n"), std::string::npos);
  EXPECT_NE(h.find("\nosteon_origin_mm:=-12.345678901234567 3.1000000000000001 0.001\n"),
            std::string::npos)
      << h;
}

TEST(NrrdIo, WithoutDensityFileDensityIsZero) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("grid.nrrd");
  const VoxelGrid grid = makeTestGrid();
  writeNrrd(grid, path);                         // leaves a density file ...
  writeNrrd(grid, path, /*withDensity=*/false);  // ... which must not be paired with it
  EXPECT_FALSE(fs::exists(densityPathFor(path)));
  const NrrdReadResult read = readNrrd(path);
  EXPECT_FALSE(read.densityLoaded);
  expectSameVoxels(grid, read.grid, false);
  EXPECT_EQ(read.grid.voxelSizeMm(), grid.voxelSizeMm());
}

TEST(NrrdIo, UniformGridStaysSparse) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("empty.nrrd");
  VoxelGrid grid({40, 33, 17}, glm::dvec3(0.0), 0.25);
  grid.setBrickUniform(7, kFillFull, 900);
  writeNrrd(grid, path);
  const NrrdReadResult read = readNrrd(path);
  EXPECT_EQ(read.grid.allocatedBrickCount(), 0u);
  EXPECT_EQ(read.grid.brickUniformFill(7), kFillFull);
  EXPECT_EQ(read.grid.brickUniformDensity(7), 900);
  EXPECT_EQ(read.grid.countVoxels(1), grid.countVoxels(1));
}

// Files as other tools write them: no osteon keys, other type spellings, spacings, big endian.
std::string handHeader(const std::string& type, const std::string& extra) {
  return "NRRD0005\n# by hand\ntype: " + type + "\ndimension: 3\nsizes: 3 2 2\nencoding: raw\n" +
         extra + "\n";
}

TEST(NrrdIo, ReadsForeignFiles) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("foreign.nrrd");
  std::string fill;
  for (int i = 0; i < 12; ++i) fill += char(i * 20);
  test::writeBytes(path, handHeader("unsigned char",
                                    "space: left-posterior-superior\r\n"
                                    "space directions: (0.5,0,0) (0,0.5,0) (0,0,0.5)\r\n"
                                    "space origin: (1,2,3)\r\n") +
                             fill);
  NrrdReadResult read = readNrrd(path);
  EXPECT_EQ(read.grid.dims(), glm::ivec3(3, 2, 2));
  EXPECT_DOUBLE_EQ(read.grid.voxelSizeMm(), 0.5);
  EXPECT_DOUBLE_EQ(read.grid.originMm().x, 0.75);  // the origin field is a voxel centre
  EXPECT_DOUBLE_EQ(read.grid.originMm().z, 2.75);
  EXPECT_EQ(read.grid.fill({2, 1, 1}), Fill(11 * 20 * kFillPerStep));
  EXPECT_FALSE(read.densityLoaded);

  // spacings instead of space directions; big-endian int16 density, byte-swapped on reading.
  test::writeBytes(path, handHeader("uchar", "spacings: 2 2 2\n") + fill);
  std::string density;
  for (int i = 0; i < 12; ++i) {
    const auto v = std::uint16_t(Density(-300 + 100 * i));
    density += char(v >> 8);
    density += char(v & 0xff);
  }
  test::writeBytes(densityPathFor(path),
                   handHeader("signed short", "endian: big\nspacings: 2 2 2\n") + density);
  read = readNrrd(path);
  EXPECT_TRUE(read.densityLoaded);
  EXPECT_EQ(read.grid.voxelSizeMm(), 2.0);
  EXPECT_EQ(read.grid.originMm(), glm::dvec3(0.0));
  EXPECT_EQ(read.grid.density({0, 0, 0}), -300);
  EXPECT_EQ(read.grid.density({2, 1, 1}), 800);
}

// Every failure is an InputError naming the file (`named`, default `path`), fast and without a
// large allocation.
void expectInputError(const std::string& path, const std::string& reason,
                      const std::string& named = "") {
  try {
    readNrrd(path);
    ADD_FAILURE() << "no error for " << path << " (expected '" << reason << "')";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(named.empty() ? path : named), std::string::npos) << what;
    EXPECT_NE(what.find(reason), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

const std::string kGoodFields =
    "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"
    "space origin: (0,0,0)\n";

TEST(NrrdIo, RejectsBadFiles) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("bad.nrrd");
  const std::string data(12, '\x01');
  expectInputError(dir.file("missing.nrrd"), "no such file");

  const struct {
    std::string bytes;
    std::string reason;
  } cases[] = {
      {"\x89PNG\r\n\x1a\n" + data, "not a NRRD file"},
      {"", "not a NRRD file"},
      {handHeader("uint8", kGoodFields) + data.substr(0, 11), "truncated"},
      {handHeader("uint8", kGoodFields) + data + "x", "disagree with sizes"},
      {handHeader("uint8", kGoodFields), "truncated"},
      {"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 2 2\nencoding: raw\n", "blank line"},
      {"NRRD0004\ntype: uint8\ndimension: 2\nsizes: 6 2\nencoding: raw\nspacings: 1 1\n\n" + data,
       "dimension '2'"},
      {handHeader("float", kGoodFields) + data + data + data + data, "type 'float'"},
      {handHeader("int16", kGoodFields) + data + data, "type 'int16'"},
      {"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 2 2\nencoding: gzip\n" + kGoodFields + "\n" +
           data,
       "gzip encoding is not supported"},
      {handHeader("uint8", "spacings: 1 1 2\n") + data, "anisotropic"},
      {handHeader("uint8", "space directions: (1,0,0) (0,1,0) (0,0,1.5)\n") + data, "anisotropic"},
      {handHeader("uint8", "space directions: (0.7,0.7,0) (-0.7,0.7,0) (0,0,1)\n") + data,
       "axis-aligned"},
      {handHeader("uint8", "space: right-anterior-superior\nspacings: 1 1 1\n") + data,
       "right-anterior-superior"},
      {handHeader("uint8", "") + data, "no spacing"},
      {handHeader("uint8", kGoodFields + "data file: bad.raw\n"), "bad.raw: no such file"},
      {"NRRD0004\ntype: uint8\ndimension: 3\nencoding: raw\nspacings: 1 1 1\n\n" + data,
       "missing 'sizes'"},
      {"NRRD0004\ndimension: 3\nsizes: 3 2 2\nencoding: raw\nspacings: 1 1 1\n\n" + data,
       "missing 'type'"},
      {"NRRD0004\ntype: uint8\nsizes: 3 2 2\nencoding: raw\nspacings: 1 1 1\n\n" + data,
       "missing 'dimension'"},
      {"NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 2 -2\nencoding: raw\nspacings: 1 1 1\n\n" +
           data,
       "sizes"},
      {handHeader("uint8", kGoodFields + "osteon_voxel_size_mm:=2\n") + data, "disagrees"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.reason);
    test::writeBytes(path, c.bytes);
    expectInputError(path, c.reason);
  }
}

// Spacing and origin are checked after they are combined: a grid beyond 1000 km would mesh to
// infinite coordinates.
TEST(NrrdIo, GridMustLieWithinAThousandKilometres) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("far.nrrd");
  const std::string data(12, '\x01');
  const struct {
    std::string fields;
    std::string reason;
  } cases[] = {
      {"spacings: 1e300 1e300 1e300\n",
       "voxel size 1e+300 mm from 'spacings' puts the far corner at x = 3e+300 mm, beyond +-1e9 mm "
       "(1000 km)"},
      {"space directions: (1e300,0,0) (0,1e300,0) (0,0,1e300)\n",
       "from 'space directions' puts the far corner"},
      {"space directions: (1e308,0,0) (0,1e308,0) (0,0,1e308)\n",
       "voxel size from 'space directions' is not a positive finite number"},
      {"osteon_voxel_size_mm:=4e8\n",
       "from 'osteon_voxel_size_mm' puts the far corner at x = 1.2e+09 mm"},
      {"space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,-2e9)\n",
       "origin from 'space origin' is at z = -2e+09 mm, beyond +-1e9 mm (1000 km)"},
      {"spacings: 1 1 1\nosteon_origin_mm:=0 5e9 0\n",
       "origin from 'osteon_origin_mm' is at y = 5e+09 mm"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.reason);
    test::writeBytes(path, handHeader("uint8", c.fields) + data);
    expectInputError(path, c.reason);
  }
  test::writeBytes(path, handHeader("uint8", "spacings: 1e8 1e8 1e8\n") + data);  // 300 km: fine
  EXPECT_DOUBLE_EQ(readNrrd(path).grid.voxelSizeMm(), 1e8);
}

TEST(NrrdIo, OverlongHeaderLineIsNamed) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("long.nrrd");
  const auto start = std::chrono::steady_clock::now();
  test::writeBytes(path, "NRRD0004\ntype: uint8\n# " + std::string(10 << 20, 'x') +
                             "\ndimension: 3\nsizes: 3 2 2\nencoding: raw\nspacings: 1 1 1\n\n" +
                             std::string(12, '\0'));
  expectInputError(path, "header line 3 is longer than 64 KiB");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0);
}

TEST(NrrdIo, LyingHeaderFailsFastWithoutAllocating) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("liar.nrrd");
  const auto start = std::chrono::steady_clock::now();
  // Beyond 2^32 voxels, and within it but far beyond the 10 bytes present.
  for (const char* sizes : {"100000 100000 100000", "1024 1024 1024", "1073741824 4 1"}) {
    test::writeBytes(path, std::string("NRRD0004\ntype: uint8\ndimension: 3\nsizes: ") + sizes +
                               "\nencoding: raw\nspacings: 1 1 1\n\n" + std::string(10, '\0'));
    EXPECT_THROW(readNrrd(path), InputError) << sizes;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 0.5);
}

TEST(NrrdIo, DensityMustMatchFill) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("grid.nrrd");
  writeNrrd(makeTestGrid(), path);
  const std::string densityPath = densityPathFor(path);
  test::writeBytes(
      densityPath,
      "NRRD0004\ntype: int16\ndimension: 3\nsizes: 4 4 4\nendian: little\nencoding: raw\n"
      "space directions: (0.54,0,0) (0,0.54,0) (0,0,0.54)\n\n" +
          std::string(128, '\0'));
  expectInputError(path, "do not match the fill file", densityPath);

  // A uint8 density file is as wrong as a mismatched one.
  writeNrrd(makeTestGrid(), path, false);
  const std::string fillBytes = test::readBytes(path);
  test::writeBytes(densityPath, fillBytes);
  expectInputError(path, "density must be int16", densityPath);
}

TEST(NrrdIo, WriteFailureIsAnInputError) {
  test::ScopedTempDir dir("nrrd");
  const std::string path = dir.file("no/such/folder/grid.nrrd");
  try {
    writeNrrd(VoxelGrid({2, 2, 2}, glm::dvec3(0.0), 1.0), path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace osteon::geometry
