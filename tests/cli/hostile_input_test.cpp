// Inputs a hostile tester tries: each gets exit 2 (1 for a failed check) and one true line on
// stderr, within bounded time and memory (the fixture's limits), and no input is ever lost.
#include "support/cli_fixture.h"
#include "support/shapes.h"

#include "osteon/geometry/mesh_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace osteon {
namespace {

namespace fs = std::filesystem;

class HostileInputTest : public CliTest {
 protected:
  void SetUp() override { geometry::writeMesh(test::makeBox({0, 0, 0}, {20, 20, 20}), path("cube.stl")); }

  // A two-row path through the cube, with `rows` appended.
  std::string writePath(const std::string& name, const std::string& rows) const {
    test::writeBytes(path(name), "t,x,y,z,drill_on\n0,10,10,30,1\n" + rows);
    return path(name);
  }
};

std::string quoted(const std::string& s) { return "'" + s + "'"; }

TEST_F(HostileInputTest, EmptyGridIsAnInputErrorNamingExtentVoxelAndUnits) {
  // A humerus in metres read as millimetres: 0.3 mm long, smaller than one voxel.
  expectBadInput("drill default --scale 0.001 --voxel-size 1.2 --path portal-5 --out-dir " + quoted(path("d")),
                 "default: a 0.05", "try --units mm");
  expectBadInput("experiment seed --mesh default --scale 0.001 --out-dir " + quoted(path("e")), "voxels of 1.2 mm",
                 "larger than the mesh");
  for (const char* threaded : {"", " --threaded"}) {
    expectBadInput(std::string("drill default --voxel-size 200 --path portal-5") + threaded + " --out-dir " +
                       quoted(path("d")),
                   "--voxel-size 200", "larger than the mesh");
  }
  // A flat, open mesh has no inside at any voxel size.
  test::writeBytes(path("flat.stl"),
                   "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
                   "endloop\nendfacet\nendsolid t\n");
  expectBadInput("drill " + quoted(path("flat.stl")) + " --voxel-size 1 --path " +
                     quoted(writePath("p.csv", "1,10,10,0,1\n")) + " --out-dir " + quoted(path("d")),
                 path("flat.stl"), "no voxel inside");
  // Nothing written for a refused run.
  EXPECT_FALSE(fs::exists(path("d/forces.csv")));
}

TEST_F(HostileInputTest, UnitsAdviceForABoneOverTwoMetres) {
  expectBadInput("experiment seed --scale 100 --out-dir " + quoted(path("e")), "default: a 5271", "try --units mm");
  const CliRun run = osteon("experiment seed --scale 100 --out-dir " + quoted(path("e")));
  EXPECT_EQ(run.err.find("--voxel-size"), std::string::npos) << "no --voxel-size was given: " << run.err;
}

TEST_F(HostileInputTest, HugeVoxelSizesAreRefusedBeforeAnyRayIsCast) {
  expectBadInput("voxelize default --voxel-size 1e18", "--voxel-size 1e+18", "larger than the mesh");
  expectBadInput("voxelize default --voxel-size 1e20 --robust", "--voxel-size 1e+20", "larger than the mesh");
  expectBadInput("mesh default --voxel-size 1e18", "--voxel-size 1e+18", "larger than the mesh");
  expectBadInput("hierarchy default --voxel-size 1e18", "--voxel-size 1e+18", "larger than the mesh");
  expectBadInput("drill default --voxel-size 1e20 --path portal-5 --out-dir " + quoted(path("d")),
                 "--voxel-size 1e+20", "larger than the mesh");
}

TEST_F(HostileInputTest, NoOutputMayOverwriteAnInput) {
  const std::string cube = test::readBytes(path("cube.stl"));
  expectBadInput("mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("cube.stl")),
                 path("cube.stl"), "same file as the input");
  expectBadInput("voxelize " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("cube.stl")),
                 path("cube.stl"), "same file as the input");
  fs::create_symlink(path("cube.stl"), path("link.stl"));
  expectBadInput("mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("link.stl")),
                 path("link.stl"), "same file as the input");
  EXPECT_EQ(test::readBytes(path("cube.stl")), cube);

  fs::create_directories(path("D"));
  const std::string csv = writePath("D/forces.csv", "1,10,10,5,1\n");
  const std::string rows = test::readBytes(csv);
  expectBadInput("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --path " + quoted(csv) + " --out-dir " +
                     quoted(path("D")),
                 "forces.csv", "same file as the input");
  EXPECT_EQ(test::readBytes(csv), rows);

  ASSERT_EQ(osteon("mesh " + quoted(path("cube.stl")) + " --voxel-size 1 --out " + quoted(path("D/surface.ply")))
                .exitCode,
            0);
  const std::string surface = test::readBytes(path("D/surface.ply"));
  expectBadInput("drill " + quoted(path("D/surface.ply")) + " --voxel-size 1 --path portal-5 --out-dir " +
                     quoted(path("D")),
                 "surface.ply", "same file as the input");
  EXPECT_EQ(test::readBytes(path("D/surface.ply")), surface);
}

TEST_F(HostileInputTest, OutputsAppearWholeOrNotAtAllAndLeaveNoTemporaryFiles) {
  const CliRun run = osteon("drill " + quoted(path("cube.stl")) + " --voxel-size 1 --levels 0 --path " +
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
  test::writeBytes(path("typed.json"),
                   "{\"schema\":\"osteon-validate/1\",\"cases\":[{\"model\":\"default\",\"pass\":\"yes\"}]}");
  expectBadInput("validate --quick --compare " + quoted(path("array.json")) + " --out-dir " + quoted(path("v")),
                 path("array.json"), "not a validate report");
  expectBadInput("validate --quick --compare " + quoted(path("cases.json")) + " --out-dir " + quoted(path("v")),
                 path("cases.json"), "not a validate report");
  expectBadInput("validate --quick --compare " + quoted(path("typed.json")) + " --out-dir " + quoted(path("v")),
                 path("typed.json"), "\"pass\" is not true or false");
  EXPECT_FALSE(fs::exists(path("v/report.json")));
}

TEST_F(HostileInputTest, ValuesThatWrapOrAreIgnoredAreRefused) {
  expectBadInput("hierarchy default --voxel-size 1.2 --seed -1", "--seed", "non-negative");
  expectBadInput("validate --quick --voxel-sizes nan --out-dir " + quoted(path("v")), "--voxel-sizes nan",
                 "not a voxel size");
  expectBadInput("validate --quick --voxel-sizes 0 --out-dir " + quoted(path("v")), "--voxel-sizes 0",
                 "not a voxel size");
  expectBadInput("validate --quick --voxel-sizes '' --out-dir " + quoted(path("v")), "--voxel-sizes",
                 "no voxel size");
}

TEST_F(HostileInputTest, ValidateNamesTheModelWhoseGridIsEmpty) {
  test::writeBytes(path("flat.stl"),
                   "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
                   "endloop\nendfacet\nendsolid t\n");
  expectBadInput("validate --quick --models " + quoted(path("flat.stl")) + " --out-dir " + quoted(path("v")),
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

}  // namespace
}  // namespace osteon
