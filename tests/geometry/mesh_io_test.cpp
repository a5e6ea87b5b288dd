#include "osteon/geometry/error.h"
#include "osteon/geometry/mesh_io.h"
#include "support/shapes.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <algorithm>
#include <limits>
#include <random>

namespace osteon::geometry {
namespace {

std::string binaryStl(const std::string& header80, std::uint32_t count,
                      const std::vector<std::array<float, 9>>& triangles) {
  std::string bytes = header80;
  bytes.resize(80, ' ');
  bytes.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0.f, 0.f, 1.f};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    bytes.append(reinterpret_cast<const char*>(t.data()), 36);
    bytes.append(2, '\0');
  }
  return bytes;
}

// The message names the file and says why.
void expectInputError(const std::string& path, const std::string& reason) {
  try {
    readMesh(path);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(reason), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
  }
}

class MeshIoTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("mesh_io");
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
  void TearDown() override { std::filesystem::remove_all(dir_); }
};

TEST_F(MeshIoTest, RoundTripsEveryFormat) {
  const TriangleMesh sphere = test::makeSphere(12.5, 48, 24, {3, -4, 5});
  const double volume = signedVolumeMm3(sphere);
  for (const char* name : {"s.stl", "s.obj", "s.ply", "s.off", "S.STL"}) {
    writeMesh(sphere, path(name));
    MeshFileInfo info;
    const TriangleMesh back = readMesh(path(name), 1.0, &info);
    EXPECT_EQ(back.triangleCount(), sphere.triangleCount()) << name;
    EXPECT_EQ(back.vertexCount(), sphere.vertexCount()) << name;
    EXPECT_NEAR(signedVolumeMm3(back), volume, 1e-5 * volume) << name;
    EXPECT_TRUE(analyzeTopology(back).closed()) << name;
    EXPECT_TRUE(analyzeTopology(back).consistentlyOriented()) << name;
  }
  writeMesh(sphere, path("ascii.stl"), /*asciiStl=*/true);
  MeshFileInfo info;
  const TriangleMesh ascii = readMesh(path("ascii.stl"), 1.0, &info);
  EXPECT_FALSE(info.binary);
  EXPECT_EQ(ascii.triangleCount(), sphere.triangleCount());
  readMesh(path("s.stl"), 1.0, &info);
  EXPECT_TRUE(info.binary);
}

TEST_F(MeshIoTest, TextFormatsKeepDoublePrecision) {
  TriangleMesh box = test::makeBox({0.1234567890123, 0, 0}, {1, 1, 1.0000000001});
  for (const char* name : {"b.obj", "b.off"}) {
    writeMesh(box, path(name));
    const TriangleMesh back = readMesh(path(name));
    ASSERT_EQ(back.vertexCount(), box.vertexCount());
    EXPECT_NEAR(bounds(back).minMm.x, 0.1234567890123, 1e-7) << name;
  }
}

TEST_F(MeshIoTest, BinaryStlWithSolidHeaderIsReadAsBinary) {
  const std::string file = path("cad.stl");
  test::writeBytes(file, binaryStl("solid part exported by a CAD system", 2,
                                   {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {1, 0, 0, 1, 1, 0, 0, 1, 0}}));
  MeshFileInfo info;
  const TriangleMesh m = readMesh(file, 1.0, &info);
  EXPECT_TRUE(info.binary);
  EXPECT_EQ(m.triangleCount(), 2u);
  EXPECT_EQ(m.vertexCount(), 4u);  // shared corners merged
}

TEST_F(MeshIoTest, PolygonsAreTriangulatedAndDamagedSoupsLoadWhole) {
  test::writeBytes(path("quad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
                                     "f 1 2 3 4\nf 1 2 5\nf 2 3 5\nf 3 4 5\nf 4 1 5\n");
  MeshFileInfo info;
  const TriangleMesh pyramid = readMesh(path("quad.obj"), 1.0, &info);
  EXPECT_EQ(pyramid.triangleCount(), 6u);
  EXPECT_EQ(info.polygonsTriangulated, 1u);
  EXPECT_EQ(info.polygonsRead, 5u);

  // A fin: an edge with three faces. OpenMesh's own kernel would drop a face; we keep all.
  TriangleMesh fin = test::makeBox({0, 0, 0}, {1, 1, 1});
  fin.positionsMm.push_back({0.5, 0.5, 3.0});
  fin.triangles.push_back({0, 1, 8});
  for (const char* name : {"fin.obj", "fin.off", "fin.ply", "fin.stl"}) {
    writeMesh(fin, path(name));
    const TriangleMesh back = readMesh(path(name));
    EXPECT_EQ(back.triangleCount(), 13u) << name;
    EXPECT_EQ(analyzeTopology(back).nonManifoldEdges, 1u) << name;
  }
}

TEST_F(MeshIoTest, UnitsScaleToMillimetres) {
  writeMesh(test::makeBox({0, 0, 0}, {0.01, 0.02, 0.03}), path("m.stl"));
  const TriangleMesh mm = readMesh(path("m.stl"), 1000.0);
  EXPECT_NEAR(bounds(mm).maxMm.z, 30.0, 1e-4);
  EXPECT_THROW(readMesh(path("m.stl"), 0.0), InputError);
  EXPECT_THROW(readMesh(path("m.stl"), std::numeric_limits<double>::quiet_NaN()), InputError);
}

TEST_F(MeshIoTest, BadInputsNameTheFileAndTheReason) {
  expectInputError(path("missing.stl"), "no such file");
  test::writeBytes(path("mesh.xyz"), "1 2 3\n");
  expectInputError(path("mesh.xyz"), "unknown mesh extension");
  test::writeBytes(path("empty.stl"), "");
  expectInputError(path("empty.stl"), "empty file");
  test::writeBytes(path("empty.obj"), "# no vertices\n");
  expectInputError(path("empty.obj"), "empty mesh");
  test::writeBytes(path("points.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expectInputError(path("points.obj"), "zero triangles");
  test::writeBytes(path("zero.stl"), binaryStl("", 0, {}));
  expectInputError(path("zero.stl"), "empty mesh");
  test::writeBytes(path("nan.obj"), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expectInputError(path("nan.obj"), "non-finite");
  test::writeBytes(path("inf.off"), "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n");
  expectInputError(path("inf.off"), "non-finite");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  test::writeBytes(path("nan.stl"), binaryStl("", 1, {{0, 0, 0, nan, 0, 0, 0, 1, 0}}));
  expectInputError(path("nan.stl"), "non-finite");
  std::string truncated = binaryStl("", 3, {{0, 0, 0, 1, 0, 0, 0, 1, 0}});
  test::writeBytes(path("truncated.stl"), truncated);
  expectInputError(path("truncated.stl"), "truncated binary STL");
  test::writeBytes(path("huge.stl"), binaryStl("", 90000000u, {{0, 0, 0, 1, 0, 0, 0, 1, 0}}));
  expectInputError(path("huge.stl"), "overflows 32-bit");
  // A count whose byte size wraps around 2^32 to exactly this file's size.
  const std::uint32_t wraps = std::uint32_t((std::uint64_t(1) << 32) / 50 + 1);
  test::writeBytes(path("wrap.stl"), binaryStl("", wraps, {{0, 0, 0, 1, 0, 0, 0, 1, 0}}));
  expectInputError(path("wrap.stl"), "overflows 32-bit");
  test::writeBytes(path("range.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expectInputError(path("range.obj"), "out of range");
  test::writeBytes(path("range.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
  expectInputError(path("range.off"), "out of range");
  test::writeBytes(path("range.ply"),
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
  expectInputError(path("range.ply"), "out of range");
  test::writeBytes(path("lying.off"), "OFF\n2000000000 1 0\n0 0 0\n");
  expectInputError(path("lying.off"), "more than its");
  test::writeBytes(path("lying.ply"),
                   "ply\nformat binary_little_endian 1.0\nelement vertex 100000000\n"
                   "property float x\nproperty float y\nproperty float z\nend_header\n");
  expectInputError(path("lying.ply"), "truncated");
  test::writeBytes(path("garbage.stl"), std::string(40, '\x7f'));
  expectInputError(path("garbage.stl"), "too short");
}

TEST_F(MeshIoTest, MalformedPlyHeadersAreRejectedBeforeParsing) {
  // Headers like these crashed or hung OpenMesh's PLY reader before the preflight.
  const std::string body = "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string good = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                           "property float y\nproperty float z\nelement face 1\n"
                           "property list uchar int vertex_indices\n";
  test::writeBytes(path("ok.ply"), good + body);
  EXPECT_EQ(readMesh(path("ok.ply")).triangleCount(), 1u);
  std::string typo = good;
  typo.replace(typo.find("element vertex"), 7, "eIement");
  test::writeBytes(path("typo.ply"), typo + body);
  expectInputError(path("typo.ply"), "unknown keyword");
  std::string format = good;
  format.replace(format.find("1.0"), 3, "\x81&1.0");
  test::writeBytes(path("format.ply"), format + body);
  expectInputError(path("format.ply"), "non-printable");
  std::string noZ = good;
  noZ.erase(noZ.find("property float z\n"), 17);
  test::writeBytes(path("noz.ply"), noZ + body);
  expectInputError(path("noz.ply"), "x, y and z");
}

TEST_F(MeshIoTest, CountsAndCornersTheParsersWouldTrustAreCheckedFirst) {
  // Each of these crashed OpenMesh's readers, or made them loop or allocate gigabytes.
  test::writeBytes(path("slash.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n");
  expectInputError(path("slash.obj"), "not a vertex index");
  test::writeBytes(path("corners.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n999999999993 0 1 2\n");
  expectInputError(path("corners.off"), "corner count");
  test::writeBytes(path("list.ply"),
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement face 1\nproperty list uint int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n");
  expectInputError(path("list.ply"), "list count");
  test::writeBytes(path("junk.ply"),
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property float z\nelement junk 1000000000000\nend_header\n0 0 0\n");
  expectInputError(path("junk.ply"), "no properties");
  test::writeBytes(path("binary.off"), "OFF BINARY\n" + std::string(40, '\0'));
  expectInputError(path("binary.off"), "binary OFF is not supported");
  test::writeBytes(path("countsOnOffLine.off"), "OFF 3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectInputError(path("countsOnOffLine.off"), "non-finite");
  test::writeBytes(path("float.obj"), "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
  expectInputError(path("float.obj"), "single precision");
}

TEST_F(MeshIoTest, AsciiStlWithByteOrderMarkOrUtf8NameIsText) {
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                            "vertex 0 1 0\nendloop\nendfacet\n";
  test::writeBytes(path("bom.stl"), "\xEF\xBB\xBFsolid t\n" + facet + "endsolid t\n");
  test::writeBytes(path("utf8.stl"), "  solid Sch\xC3\xA4" "del\n" + facet + "endsolid\n");
  for (const char* name : {"bom.stl", "utf8.stl"}) {
    MeshFileInfo info;
    EXPECT_EQ(readMesh(path(name), 1.0, &info).triangleCount(), 1u) << name;
    EXPECT_FALSE(info.binary) << name;
  }
}

// Random damage to valid files of every format: each read returns a mesh or an InputError,
// never a crash, a hang or another exception (fixed seed, so a failure reproduces).
TEST_F(MeshIoTest, MutatedFilesNeverCrashOrHang) {
  std::vector<std::pair<std::string, std::string>> seeds;
  for (const char* name : {"seed.stl", "seed.obj", "seed.ply", "seed.off"}) {
    writeMesh(test::makeSphere(5.0, 6, 4), path(name));
    seeds.emplace_back(name, test::readBytes(path(name)));
  }
  writeMesh(test::makeSphere(5.0, 6, 4), path("ascii.stl"), true);
  seeds.emplace_back("ascii.stl", test::readBytes(path("ascii.stl")));
  std::mt19937 rng(20261121);
  int accepted = 0, rejected = 0;
  for (int round = 0; round < 400; ++round) {
    const auto& [name, original] = seeds[std::size_t(round) % seeds.size()];
    std::string bytes = original;
    const int edits = 1 + int(rng() % 6);
    for (int e = 0; e < edits && !bytes.empty(); ++e) {
      const std::size_t at = rng() % bytes.size();
      switch (rng() % 4) {
        case 0: bytes[at] = char(rng() % 256); break;
        case 1: bytes[at] = "0123456789 -.e\n"[rng() % 15]; break;
        case 2: bytes.erase(at, 1 + rng() % 20); break;
        default: bytes.insert(at, std::string(1 + rng() % 4, char(rng() % 256))); break;
      }
    }
    const std::string file = path("m" + std::to_string(round) + "_" + name);
    test::writeBytes(file, bytes);
    try {
      const TriangleMesh m = readMesh(file);
      EXPECT_FALSE(m.triangles.empty());
      for (const glm::u32vec3& t : m.triangles) {
        ASSERT_LT(std::max({t.x, t.y, t.z}), m.vertexCount()) << file;
      }
      ++accepted;
    } catch (const InputError&) {
      ++rejected;
    }
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(rejected, 0);
}

TEST(SharedData, RealBonesLoadInTheirUnits) {
  const std::string dir = OSTEON_SHARED_DATA_DIR;
  if (!std::filesystem::exists(dir + "/humerus_R_opensim_myosuite.stl")) {
    GTEST_SKIP() << "shared data not found at " << dir;
  }
  const TriangleMesh humerus = readMesh(dir + "/humerus_R_opensim_myosuite.stl", 1000.0);
  EXPECT_EQ(humerus.triangleCount(), 676u);
  EXPECT_NEAR(bounds(humerus).extentMm().y, 318.0, 10.0);  // 0.318 m long
  EXPECT_TRUE(analyzeTopology(humerus).closed());
  const TriangleMesh fibula = readMesh(dir + "/fibula_L_vhm_denver.stl");
  EXPECT_EQ(fibula.triangleCount(), 32994u);
  EXPECT_GT(signedVolumeMm3(fibula), 0.0);
}

}  // namespace
}  // namespace osteon::geometry
