// Messages that must carry their reason and their file: `check` verdicts on surfaces that are
// closed but no solid, `voxelize --out` with a name that is not NRRD, a link loop and a NUL
// byte in a file name, a head fit that names its mesh, and gnuplot's real trouble (not
// "is gnuplot installed?" when the shell around it failed under a low `ulimit -n`).
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"
#include "support/files.h"

namespace osteon {
namespace {

using nlohmann::json;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

// An OBJ of two UV spheres around the origin (radii 10 and 5 mm), the inner one facing
// outward too (flipInner false) or inward.
std::string twoSpheresObj(bool flipInner) {
  std::string obj;
  int base = 1;
  for (const double radiusMm : {10.0, 5.0}) {
    const geometry::TriangleMesh s = test::makeSphere(radiusMm, 16, 8);
    for (const glm::dvec3& p : s.positionsMm) {
      obj +=
          "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    }
    const bool flip = flipInner && radiusMm < 10.0;
    for (const glm::u32vec3& t : s.triangles) {
      obj += "f " + std::to_string(base + int(t.x)) + " " +
             std::to_string(base + int(flip ? t.z : t.y)) + " " +
             std::to_string(base + int(flip ? t.y : t.z)) + "\n";
    }
    base += int(s.positionsMm.size());
  }
  return obj;
}

TEST_F(CliTest, CheckFailsClosedSurfacesThatAreNoSolidForTheirReason) {
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  // Both sides on one diagonal: that edge has four triangles (non-manifold), and no border.
  test::writeBytes(path("sheet.obj"), square + "f 1 2 3\nf 1 3 4\nf 1 3 2\nf 1 4 3\n");
  // Both sides, crossing diagonals: closed and manifold, enclosing nothing.
  test::writeBytes(path("flat.obj"), square + "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
  test::writeBytes(path("nested.obj"), twoSpheresObj(false));
  test::writeBytes(path("hollow.obj"), twoSpheresObj(true));

  const CliRun sheet = osteon("check " + quoted(path("sheet.obj")) + " --cracks 64 --json");
  EXPECT_EQ(sheet.exitCode, 1) << sheet.err;
  const json s = json::parse(sheet.out);
  EXPECT_EQ(s["border_edges"], 0);
  for (const auto& f : s["failures"])
    EXPECT_EQ(f.get<std::string>().find("open"), std::string::npos) << f;
  EXPECT_NE(s["failures"].dump().find("non-manifold: 1 edges of more than two triangles"),
            std::string::npos)
      << s["failures"];

  const CliRun flat = osteon("check " + quoted(path("flat.obj")) + " --cracks 64 --json");
  EXPECT_EQ(flat.exitCode, 1) << flat.err;
  EXPECT_NE(json::parse(flat.out)["failures"].dump().find("encloses no volume"), std::string::npos)
      << flat.out;

  const CliRun nested = osteon("check " + quoted(path("nested.obj")) + " --cracks 64 --json");
  EXPECT_EQ(nested.exitCode, 1) << nested.out;
  const json n = json::parse(nested.out);
  EXPECT_EQ(n["verdict"], "FAIL");
  EXPECT_EQ(n["winding_number_max"], 2);
  EXPECT_NE(n["failures"].dump().find("nested shells: winding number 2"), std::string::npos)
      << n["failures"];

  const CliRun hollow = osteon("check " + quoted(path("hollow.obj")) + " --cracks 64 --json");
  EXPECT_EQ(hollow.exitCode, 0) << hollow.out;  // a hollow ball is a solid
}

TEST_F(CliTest, VoxelizeRefusesAGridNameThatIsNotNrrd) {
  expectBadInput("voxelize default --voxel-size 2 --out " + quoted(path("grid.ply")),
                 "--out " + path("grid.ply"), "must end in .nrrd");
  expectBadInput("voxelize default --voxel-size 2 --out " + quoted(path("grid")),
                 "--out " + path("grid"), "not nothing");
  EXPECT_FALSE(std::filesystem::exists(path("grid.ply")));
  EXPECT_EQ(osteon("voxelize default --voxel-size 2 --out " + quoted(path("grid.NRRD"))).exitCode,
            0);
}

TEST_F(CliTest, ALinkLoopAndANulByteInANameSayWhat) {
  std::filesystem::create_symlink(path("b.stl"), path("a.stl"));
  std::filesystem::create_symlink(path("a.stl"), path("b.stl"));
  std::filesystem::create_symlink(path("b.nrrd"), path("a.nrrd"));
  std::filesystem::create_symlink(path("a.nrrd"), path("b.nrrd"));
  std::filesystem::create_symlink(path("b.csv"), path("a.csv"));
  std::filesystem::create_symlink(path("a.csv"), path("b.csv"));
  expectBadInput("info " + quoted(path("a.stl")), path("a.stl"),
                 "too many levels of symbolic links");
  expectBadInput("mesh " + quoted(path("a.nrrd")) + " --out " + quoted(path("o.ply")),
                 path("a.nrrd"), "too many levels of symbolic links");
  expectBadInput(
      "replay " + quoted(path("a.csv")) + " default --voxel-size 2 --out-dir " + quoted(path("o")),
      path("a.csv"), "too many levels of symbolic links");
  expectBadInput("drill default --voxel-size 2 --path " + quoted(path("a.csv")) + " --out-dir " +
                     quoted(path("o")),
                 path("a.csv"), "too many levels of symbolic links");
  // A detached header naming its data with a NUL byte in it (the system would see "a").
  test::writeBytes(path("a"), std::string(8, '\1'));
  const char header[] =
      "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nspacings: 1 1 1\nencoding: raw\n"
      "data file: a\0b.raw\n\n";
  test::writeBytes(path("nul.nhdr"), std::string(header, sizeof header - 1));
  expectBadInput("mesh " + quoted(path("nul.nhdr")) + " --out " + quoted(path("o.ply")),
                 "a\\0b.raw", "the file name contains a NUL byte");
}

TEST_F(CliTest, AHeadThatCannotBeFittedNamesItsMesh) {
  test::writeBytes(path("ball.obj"), twoSpheresObj(true));
  expectBadInput("drill " + quoted(path("ball.obj")) +
                     " --voxel-size 1 --path portal-5 --out-dir " + quoted(path("o")),
                 path("ball.obj") + ": humeral head fit: ", "");
}

TEST_F(CliTest, ExperimentSaysWhyGnuplotCouldNotDraw) {
  // Under `ulimit -n 8` the shell around gnuplot failed and was blamed on gnuplot; gnuplot itself
  // draws fine with that many files.
  const std::string dir = path("exp");
  // (runShell makes the redirections before the limit: this shell's own would fail under it.)
  const CliRun limited = test::runShell("ulimit -n 8; exec '" + std::string(OSTEON_CLI) +
                                            "' experiment seed --out-dir " + quoted(dir),
                                        "/dev/null", path("err"));
  EXPECT_EQ(limited.exitCode, 0) << limited.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/fig6_1.2mm_portal-5.png"));
  // No gnuplot on PATH: said so, not guessed.
  const CliRun missing = test::runShell("PATH=/nonexistent '" + std::string(OSTEON_CLI) +
                                            "' experiment seed --out-dir " + quoted(path("exp3")),
                                        "/dev/null", path("err3"));
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_NE(missing.err.find("gnuplot: not found on PATH"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace osteon
