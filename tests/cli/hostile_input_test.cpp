// Inputs a hostile tester tries: each gets exit 2 (1 for a failed check) and one true line on
// stderr, within bounded time and memory (the fixture's limits), and no input is ever lost.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;

class HostileInputTest : public CliTest {
 protected:
  void SetUp() override {
    geometry::writeMesh(test::makeBox({0, 0, 0}, {20, 20, 20}), path("cube.stl"));
  }

  // A two-row path through the cube, with `rows` appended.
  std::string writePath(const std::string& name, const std::string& rows) const {
    test::writeBytes(path(name), "t,x,y,z,drill_on\n0,10,10,30,1\n" + rows);
    return path(name);
  }
};

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

TEST_F(HostileInputTest, EmptyGridIsAnInputErrorNamingExtentVoxelAndUnits) {
  // A humerus in metres read as millimetres: 0.3 mm long, smaller than one voxel.
  expectBadInput(
      "drill default --scale 0.001 --voxel-size 1.2 --path portal-5 --out-dir " + quoted(path("d")),
      "default: a 0.05", "try --units mm");
  expectBadInput("experiment seed --mesh default --scale 0.001 --out-dir " + quoted(path("e")),
                 "voxels of 1.2 mm", "larger than the mesh");
  for (const char* threaded : {"", " --threaded"}) {
    expectBadInput(std::string("drill default --voxel-size 200 --path portal-5") + threaded +
                       " --out-dir " + quoted(path("d")),
                   "--voxel-size 200", "larger than the mesh");
  }
  // A flat, open mesh has no inside at any voxel size.
  test::writeBytes(
      path("flat.stl"),
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
      "endloop\nendfacet\nendsolid t\n");
  expectBadInput("drill " + quoted(path("flat.stl")) + " --voxel-size 1 --path " +
                     quoted(writePath("p.csv", "1,10,10,0,1\n")) + " --out-dir " +
                     quoted(path("d")),
                 path("flat.stl"), "no voxel inside");
  // Nothing written for a refused run.
  EXPECT_FALSE(fs::exists(path("d/forces.csv")));
}

TEST_F(HostileInputTest, UnitsAdviceForABoneOverTwoMetres) {
  expectBadInput("experiment seed --scale 100 --out-dir " + quoted(path("e")), "default: a 5271",
                 "try --units mm");
  const CliRun run = osteon("experiment seed --scale 100 --out-dir " + quoted(path("e")));
  EXPECT_EQ(run.err.find("--voxel-size"), std::string::npos)
      << "no --voxel-size was given: " << run.err;
}

TEST_F(HostileInputTest, HugeVoxelSizesAreRefusedBeforeAnyRayIsCast) {
  expectBadInput("voxelize default --voxel-size 1e18", "--voxel-size 1e+18",
                 "larger than the mesh");
  expectBadInput("voxelize default --voxel-size 1e20 --robust", "--voxel-size 1e+20",
                 "larger than the mesh");
  expectBadInput("mesh default --voxel-size 1e18", "--voxel-size 1e+18", "larger than the mesh");
  expectBadInput("hierarchy default --voxel-size 1e18", "--voxel-size 1e+18",
                 "larger than the mesh");
  expectBadInput("drill default --voxel-size 1e20 --path portal-5 --out-dir " + quoted(path("d")),
                 "--voxel-size 1e+20", "larger than the mesh");
}

TEST_F(HostileInputTest, NoOutputMayOverwriteAnInput) {
  const std::string cube = test::readBytes(path("cube.stl"));
  expectBadInput(
      "mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("cube.stl")),
      path("cube.stl"), "same file as the input");
  expectBadInput(
      "voxelize " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("cube.stl")),
      path("cube.stl"), "same file as the input");
  fs::create_symlink(path("cube.stl"), path("link.stl"));
  expectBadInput(
      "mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("link.stl")),
      path("link.stl"), "same file as the input");
  EXPECT_EQ(test::readBytes(path("cube.stl")), cube);

  fs::create_directories(path("D"));
  const std::string csv = writePath("D/forces.csv", "1,10,10,5,1\n");
  const std::string rows = test::readBytes(csv);
  expectBadInput("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --path " + quoted(csv) +
                     " --out-dir " + quoted(path("D")),
                 "forces.csv", "same file as the input");
  EXPECT_EQ(test::readBytes(csv), rows);

  ASSERT_EQ(osteon("mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " +
                   quoted(path("D/surface.ply")))
                .exitCode,
            0);
  const std::string surface = test::readBytes(path("D/surface.ply"));
  expectBadInput("drill " + quoted(path("D/surface.ply")) +
                     " --voxel-size 1 --path portal-5 --out-dir " + quoted(path("D")),
                 "surface.ply", "same file as the input");
  EXPECT_EQ(test::readBytes(path("D/surface.ply")), surface);
}

TEST_F(HostileInputTest, OutputsAppearWholeOrNotAtAllAndLeaveNoTemporaryFiles) {
  const CliRun run =
      osteon("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --levels 0 --path " +
             quoted(writePath("p.csv", "0.2,10,10,5,1\n")) + " --out-dir " + quoted(path("out")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  std::size_t files = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(path("out"))) {
    ++files;
    EXPECT_NE(e.path().filename().string()[0], '.') << "temporary file left: " << e.path();
  }
  EXPECT_EQ(files, 3u);
  // A refused write (the folder is a file) leaves nothing half written beside it.
  test::writeBytes(path("blocker"), "x");
  const CliRun bad = osteon("mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " +
                            quoted(path("blocker/out.ply")));
  EXPECT_EQ(bad.exitCode, 2) << bad.err;
}

TEST_F(HostileInputTest, CompareFileOfTheWrongShapeIsRefusedBeforeTheRun) {
  test::writeBytes(path("array.json"), "[1,2]");
  test::writeBytes(path("cases.json"), "{\"cases\":5}");
  test::writeBytes(
      path("typed.json"),
      "{\"schema\":\"osteon-validate/1\",\"cases\":[{\"model\":\"default\",\"pass\":\"yes\"}]}");
  expectBadInput("validate --quick --compare " + quoted(path("array.json")) + " --out-dir " +
                     quoted(path("v")),
                 path("array.json"), "not a validate report");
  expectBadInput("validate --quick --compare " + quoted(path("cases.json")) + " --out-dir " +
                     quoted(path("v")),
                 path("cases.json"), "not a validate report");
  expectBadInput("validate --quick --compare " + quoted(path("typed.json")) + " --out-dir " +
                     quoted(path("v")),
                 path("typed.json"), "\"pass\" is not true or false");
  EXPECT_FALSE(fs::exists(path("v/report.json")));
}

TEST_F(HostileInputTest, ValuesThatWrapOrAreIgnoredAreRefused) {
  expectBadInput("hierarchy default --voxel-size 1.2 --seed -1", "--seed", "non-negative");
  expectBadInput("validate --quick --voxel-sizes nan --out-dir " + quoted(path("v")),
                 "--voxel-sizes nan", "not a voxel size");
  expectBadInput("validate --quick --voxel-sizes 0 --out-dir " + quoted(path("v")),
                 "--voxel-sizes 0", "not a voxel size");
  expectBadInput("validate --quick --voxel-sizes '' --out-dir " + quoted(path("v")),
                 "--voxel-sizes", "no voxel size");
}

TEST_F(HostileInputTest, ValidateNamesTheModelWhoseGridIsEmpty) {
  test::writeBytes(
      path("flat.stl"),
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
      "endloop\nendfacet\nendsolid t\n");
  expectBadInput(
      "validate --quick --models " + quoted(path("flat.stl")) + " --out-dir " + quoted(path("v")),
      path("flat.stl"), "no voxel inside");
}

TEST_F(HostileInputTest, CheckFailsAnInsideOutSurfaceAndSaysWhy) {
  geometry::TriangleMesh box = test::makeBox({0, 0, 0}, {20, 20, 20});
  for (glm::uvec3& t : box.triangles) std::swap(t.y, t.z);
  geometry::writeMesh(box, path("inside_out.stl"));
  const CliRun run = osteon("check " + quoted(path("inside_out.stl")) + " --cracks 64 --json");
  EXPECT_EQ(run.exitCode, 1) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["verdict"], "FAIL");
  EXPECT_FALSE(j["outward_oriented"].get<bool>());
  ASSERT_EQ(j["failures"].size(), 1u);
  EXPECT_NE(j["failures"][0].get<std::string>().find("inside-out"), std::string::npos);
  // The same box facing outward passes.
  const CliRun good = osteon("check " + quoted(path("cube.stl")) + " --cracks 64 --json");
  EXPECT_EQ(good.exitCode, 0) << good.out;
}

TEST_F(HostileInputTest, MalformedTextIsRefusedNamingTheLineWithinBoundedMemory) {
  const std::string plyHead =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  test::writeBytes(path("abc.ply"), plyHead + "0 0 0\n0 1 abc\n1 0 0\n3 0 1 2\n");
  expectBadInput("info " + quoted(path("abc.ply")), "line 11", "'abc' is not a number");
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 "
      "0\nendloop\nendfacet\n";
  test::writeBytes(path("banana.stl"),
                   "solid x\nfacet normal 0 0 1\nouter loop\nvertex 1 2 banana\nvertex 1 0 0\n"
                   "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
  expectBadInput("info " + quoted(path("banana.stl")), "line 4", "'banana' is not a number");
  test::writeBytes(path("1x.stl"),
                   "solid x\nfacet normal 0 0 1\nouter loop\nvertex 1x 0 0\nvertex 1 0 0\n"
                   "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
  expectBadInput("info " + quoted(path("1x.stl")), "line 4", "'1x' is not a number");
  test::writeBytes(path("four.stl"),
                   "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                   "vertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid x\n");
  expectBadInput("info " + quoted(path("four.stl")), "line 7", "expected 'endloop'");
  // Text STL faults are told as such, not as a binary STL's triangle count.
  test::writeBytes(path("nosolid.stl"), facet + "endsolid x\n");
  expectBadInput("info " + quoted(path("nosolid.stl")), "line 1", "must begin with 'solid'");
  test::writeBytes(path("control.stl"),
                   "solid x\n" + facet.substr(0, 20) + "\x01" + facet.substr(20) + "endsolid x\n");
  expectBadInput("info " + quoted(path("control.stl")), "line 3", "control byte 0x01");
  test::writeBytes(path("nul.stl"), "solid x\n" + facet + "endsolid x\n" + std::string(3, '\0'));
  const CliRun padded = osteon("info " + quoted(path("nul.stl")));
  EXPECT_EQ(padded.exitCode, 0) << padded.err;  // trailing NUL padding is read as the text it ends
  test::writeBytes(path("abc.obj"), "v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n");
  expectBadInput("info " + quoted(path("abc.obj")), "line 2", "'abc' is not a number");
  test::writeBytes(path("two.off"), "OFF\n3 1 0\n0 0 0\n1 2\n0 1 0\n3 0 1 2\n");
  expectBadInput("info " + quoted(path("two.off")), "line 4", "needs 3 coordinates");
  // A 10 MB comment line in a grid header.
  test::writeBytes(path("long.nrrd"),
                   "NRRD0004\n# " + std::string(10 << 20, 'c') + "\ntype: uint8\n");
  expectBadInput("mesh " + quoted(path("long.nrrd")), "line 2", "longer than");
}

TEST_F(HostileInputTest, NumbersThatOverflowAfterScalingAreRefused) {
  expectBadInput("info " + quoted(path("cube.stl")) + " --scale 1e308", path("cube.stl"),
                 "beyond +-1e9 mm");
  expectBadInput("voxelize " + quoted(path("cube.stl")) + " --scale 1e300 --voxel-size 1e299",
                 path("cube.stl"), "beyond +-1e9 mm");
  // A grid from another tool, its spacing beyond any bone.
  test::writeBytes(path("huge.nrrd"),
                   "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\n"
                   "spacings: 1e300 1e300 1e300\nencoding: raw\n\n" +
                       std::string(8, '\xff'));
  expectBadInput("mesh " + quoted(path("huge.nrrd")) + " --out " + quoted(path("huge.stl")),
                 path("huge.nrrd"), "1000 km");
  EXPECT_FALSE(fs::exists(path("huge.stl")));
}

TEST_F(HostileInputTest, PathsAreBoundedNormalisedAndMayStartWithAByteOrderMark) {
  for (const char* end : {"1e300", "10000", "1e12"}) {
    expectBadInput("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --path " +
                       quoted(writePath("long.csv", std::string(end) + ",10,10,5,1\n")) +
                       " --out-dir " + quoted(path("d")),
                   "long.csv:3", "3600 s");
  }
  test::writeBytes(path("bom.csv"), "\xEF\xBB\xBFt,x,y,z,drill_on\n0,10,10,30,1\n0.1,10,10,15,1\n");
  const CliRun bom =
      osteon("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --levels 0 --path " +
             quoted(path("bom.csv")) + " --out-dir " + quoted(path("bom")));
  EXPECT_EQ(bom.exitCode, 0) << bom.err;
  // A quaternion of huge components is the same orientation as its small multiple.
  const std::string head = "t,x,y,z,drill_on,qw,qx,qy,qz\n";
  test::writeBytes(path("q1.csv"), head + "0,10,10,30,1,1,1,0,0\n0.2,10,10,15,1,1,1,0,0\n");
  test::writeBytes(path("q2.csv"),
                   head + "0,10,10,30,1,1e300,1e300,0,0\n0.2,10,10,15,1,1e300,1e300,0,0\n");
  for (const char* q : {"q1", "q2"}) {
    ASSERT_EQ(osteon("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --levels 0 --path " +
                     quoted(path(std::string(q) + ".csv")) + " --out-dir " + quoted(path(q)))
                  .exitCode,
              0);
  }
  EXPECT_EQ(test::readBytes(path("q1/forces.csv")), test::readBytes(path("q2/forces.csv")));
}

}  // namespace
}  // namespace osteon
