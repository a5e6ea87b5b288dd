#include "osteon/geometry/io/mesh_io.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/mesh_source.h"
#include "support/files.h"
#include "support/shapes.h"

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
  test::writeBytes(path("quad.obj"),
                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
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
  const std::string good =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
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
  test::writeBytes(path("nan.off"), "OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectInputError(path("nan.off"), "non-finite");
  // OpenMesh reads the counts after the OFF line: on it they would be skipped (found by fuzzing,
  // tests/data/bad/off/fuzz_counts_on_off_line.off), and a comment before them fails it.
  test::writeBytes(path("countsOnOffLine.off"), "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectInputError(path("countsOnOffLine.off"), "OFF counts must be on the line after 'OFF'");
  test::writeBytes(path("comment.off"),
                   "OFF\n# made by hand\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expectInputError(path("comment.off"), "a comment before the OFF counts");
  test::writeBytes(path("float.obj"), "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
  expectInputError(path("float.obj"), "single precision");
}

TEST_F(MeshIoTest, AsciiStlWithByteOrderMarkOrUtf8NameIsText) {
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\n";
  test::writeBytes(path("bom.stl"), "\xEF\xBB\xBFsolid t\n" + facet + "endsolid t\n");
  test::writeBytes(path("utf8.stl"),
                   "  solid Sch\xC3\xA4"
                   "del\n" +
                       facet + "endsolid\n");
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
        case 0:
          bytes[at] = char(rng() % 256);
          break;
        case 1:
          bytes[at] = "0123456789 -.e\n"[rng() % 15];
          break;
        case 2:
          bytes.erase(at, 1 + rng() % 20);
          break;
        default:
          bytes.insert(at, std::string(1 + rng() % 4, char(rng() % 256)));
          break;
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

// ASCII PLY bodies are walked token by token before OpenMesh reads them: its reader loops
// and allocates without bound once a token fails to parse.
TEST_F(MeshIoTest, AsciiPlyValuesMustBeNumbersOfTheirType) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar red\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const struct {
    const char* body;
    const char* reason;
  } cases[] = {
      {"0 0 0 1\n0 1 abc 1\n0 1 0 1\n3 0 1 2\n",
       "line 12: element 'vertex' record 1: value 'abc' is not a number (property z is float)"},
      {"0 0 0 1\n1x 0 0 1\n0 1 0 1\n3 0 1 2\n",
       "line 12: element 'vertex' record 1: value '1x' is not a number"},
      {"0 0 0 1\n1 0 0 1.5\n0 1 0 1\n3 0 1 2\n",
       "line 12: element 'vertex' record 1: value '1.5' is not an integer (property red is uchar)"},
      {"0 0 0 1\n1 0 0 300\n0 1 0 1\n3 0 1 2\n",
       "line 12: element 'vertex' record 1: value '300' is out of range (property red is uchar)"},
      {"0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 x 2\n",
       "line 14: element 'face' record 0: value 'x' is not an integer (property vertex_indices is "
       "int)"},
      {"0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2.0\n",
       "line 14: element 'face' record 0: value '2.0' is not an integer"},
      {"0 0 0 1 7\n1 0 0 1\n0 1 0 1\n3 0 1 2\n",
       "line 11: element 'vertex' record 0 ends before the line does (extra value '7')"},
      {"0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2\n\n1 2 3\n",
       "line 16: extra value '1' after the last element"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.body);
    test::writeBytes(path("bad.ply"), head + c.body);
    expectInputError(path("bad.ply"), c.reason);
  }
  // Records may span lines; CRLF, blank lines and trailing blanks are fine.
  test::writeBytes(path("ok.ply"), head + "0 0 0 1 \r\n1 0\n 0 1\r\n\r\n0 1 0 255\n3 0 1 2  \n\n");
  EXPECT_EQ(readMesh(path("ok.ply")).triangleCount(), 1u);
}

TEST_F(MeshIoTest, ScaledCoordinatesMustStayWithinAThousandKilometres) {
  writeMesh(test::makeBox({0, 0, 0}, {1, 2, 3}), path("box.stl"));
  for (const double scale : {1e308, 1e300, 1e9}) {
    SCOPED_TRACE(scale);
    try {
      readMesh(path("box.stl"), scale);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path("box.stl") + ": vertex "), std::string::npos) << what;
      EXPECT_NE(what.find("beyond +-1e9 mm (1000 km); check units/scale"), std::string::npos)
          << what;
    }
  }
  EXPECT_NO_THROW(readMesh(path("box.stl"), 1e8));  // 300 km: large but representable
  test::writeBytes(path("far.obj"), "v 0 0 0\nv 2e9 0 0\nv 0 1 0\nf 1 2 3\n");
  expectInputError(path("far.obj"), "vertex 1 coordinate 2e+09 mm after scaling by 1 is beyond");
  try {
    loadMeshArgument(kDefaultModelArgument, 1e300);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("default: vertex ", 0), 0u) << what;
    EXPECT_NE(what.find("check units/scale"), std::string::npos) << what;
  }
  EXPECT_GT(signedVolumeMm3(loadMeshArgument(kDefaultModelArgument, 1000.0)), 0.0);
}

TEST_F(MeshIoTest, AsciiStlStructureIsStrict) {
  const auto facet = [](const std::string& a, const std::string& b, const std::string& c) {
    return "facet normal 0 0 1\nouter loop\nvertex " + a + "\nvertex " + b + "\nvertex " + c +
           "\nendloop\nendfacet\n";
  };
  const std::string ok = facet("0 0 0", "1 0 0", "0 1 0");
  const struct {
    std::string text;
    const char* reason;
  } cases[] = {
      {"solid t\n" + facet("0 0 0", "1 0 0", "0 1 banana") + "endsolid t\n",
       "line 6: vertex coordinate 'banana' is not a number"},
      {"solid t\n" + facet("1x 0 0", "1 0 0", "0 1 0") + "endsolid t\n",
       "line 4: vertex coordinate '1x' is not a number"},
      {"solid t\n" + facet("0 0 0", "1 0", "0 1 0") + "endsolid t\n",
       "line 5: a vertex needs exactly 3 coordinates"},
      {"solid t\n" + facet("0 0 0", "1 0 0 1", "0 1 0") + "endsolid t\n",
       "line 5: a vertex needs exactly 3 coordinates"},
      {"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "vertex 1 1 0\nendloop\nendfacet\nendsolid t\n",
       "line 7: expected 'endloop', found 'vertex 1 1 0'"},
      {"solid t\nfacet normal 0 0 1\nouter loop\n\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "endloop\nendfacet\nendsolid t\n",
       "line 4: expected 'vertex x y z', found ''"},
      {"solid t\nfacet normal 0 0\n" + ok.substr(ok.find("outer")) + "endsolid t\n",
       "line 2: expected 'facet normal nx ny nz', found 'facet normal 0 0'"},
      {"solid t\n" + ok + "endsolid t\nvertex 1 2 3\n",
       "line 10: expected 'solid' or the end of the file, found 'vertex 1 2 3'"},
      {"solid t\n" + ok + ok, "line 15: the file ends without 'endsolid' (truncated?)"},
      {"solid t\n" + ok.substr(0, ok.find("endloop")),
       "line 6: the file ends inside a facet (truncated?)"},
      {"solid outer_shell\n" + ok + "endsolid\n", "line 1: the solid name contains 'outer'"},
      {"solid t\nfacet normal 0 0 1\nOuter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "endloop\nendfacet\nendsolid t\n",
       "line 3: expected 'outer loop' (lower or upper case), found 'Outer loop'"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.reason);
    test::writeBytes(path("bad.stl"), c.text);
    expectInputError(path("bad.stl"), c.reason);
  }
  // Several solids, NaN normals (the reader ignores normals), CRLF, upper case and indents.
  test::writeBytes(path("two.stl"),
                   "solid a\r\n" + ok +
                       "endsolid a\r\n\r\nSOLID B\r\n"
                       "  FACET NORMAL nan -nan NaN\r\n    OUTER LOOP\r\n"
                       "      VERTEX 0 0 1\r\n      VERTEX 1 0 1\r\n      VERTEX 0 1 1\r\n"
                       "    ENDLOOP\r\n  ENDFACET\r\nENDSOLID B\r\n");
  EXPECT_EQ(readMesh(path("two.stl")).triangleCount(), 2u);
}

TEST_F(MeshIoTest, ObjAndOffVertexLinesNeedThreeNumbers) {
  const struct {
    const char* name;
    const char* text;
    const char* reason;
  } cases[] = {
      {"abc.obj", "v 0 0 0\nv 0 abc 0\nv 0 1 0\nf 1 2 3\n",
       "line 2: vertex coordinate 'abc' is not a number"},
      {"two.obj", "v 0 0 0\nv 1 2\nv 0 1 0\nf 1 2 3\n", "line 2: a vertex needs 3 coordinates"},
      {"hex.obj", "v 0 0 0\nv 0x10 0 0\nv 0 1 0\nf 1 2 3\n",
       "line 2: vertex coordinate '0x10' is not a number"},
      {"abc.off", "OFF\n3 1 0\n0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n",
       "line 4: vertex coordinate 'abc' is not a number"},
      {"two.off", "OFF\n3 1 0\n0 0 0\n1 2\n0 1 0\n3 0 1 2\n",
       "line 4: a vertex needs 3 coordinates"},
      {"index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 x 2\n",
       "line 6: face index 'x' is not a vertex index"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    test::writeBytes(path(c.name), c.text);
    expectInputError(path(c.name), c.reason);
  }
  // A trailing w or colour values after x y z are fine.
  test::writeBytes(path("extra.obj"), "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(readMesh(path("extra.obj")).triangleCount(), 1u);
  test::writeBytes(path("colour.off"), "OFF\n3 1 0\n0 0 0 255 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(readMesh(path("colour.off")).triangleCount(), 1u);
  // A face colour is not: OpenMesh would read it as the next face (4 faces became 7).
  test::writeBytes(path("face_colour.off"),
                   "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0 0 255\n3 0 2 1\n");
  expectInputError(path("face_colour.off"), "face colours are not supported");
}

// A text STL that breaks the rules is reported as text, not as a binary file with a wild count.
TEST_F(MeshIoTest, TextStlProblemsAreNotReportedAsBinary) {
  const std::string body =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\n";
  test::writeBytes(path("control.stl"),
                   "solid t\n" + body.substr(0, 50) + "\x01" + body.substr(50) + "endsolid t\n");
  expectInputError(path("control.stl"), "line 5: control byte 0x01 in an ASCII STL");
  test::writeBytes(path("nosolid.stl"), body + "endsolid t\n");
  expectInputError(path("nosolid.stl"), "line 1: an ASCII STL must begin with 'solid'");
  test::writeBytes(path("nul.stl"), "solid t\n" + body.substr(0, 30) + std::string(1, '\0') +
                                        body.substr(30) + "endsolid t\n");
  expectInputError(path("nul.stl"), "line 4: control byte 0x00 in an ASCII STL");
  // NUL padding after the last line, as some exporters write to fill a block, is accepted.
  test::writeBytes(path("padded.stl"),
                   "solid t\n" + body + "endsolid t\n" + std::string(300, '\0'));
  MeshFileInfo info;
  EXPECT_EQ(readMesh(path("padded.stl"), 1.0, &info).triangleCount(), 1u);
  EXPECT_FALSE(info.binary);
  test::writeBytes(path("padded2.stl"),
                   "solid t\n" + body + "endsolid t" + std::string(5000, '\0'));
  EXPECT_EQ(readMesh(path("padded2.stl")).triangleCount(), 1u);
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
