// Every command opens its bone through BoneModel::open (or loadBoneMesh for a mesh alone): a bad
// source is refused with the same one line whichever command was given it.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"

namespace osteon {
namespace {

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

class BoneSourceCliTest : public CliTest {
 protected:
  // Runs each command line and expects exit 2 and the one stderr line `line` from all of them.
  void expectSameRefusal(const std::vector<std::string>& commands, const std::string& line) const {
    for (const std::string& command : commands) {
      const CliRun run = osteon(command);
      EXPECT_EQ(run.exitCode, 2) << command << "\n" << run.err;
      EXPECT_TRUE(run.out.empty()) << command << "\n" << run.out;
      EXPECT_EQ(run.err, line + "\n") << command;
    }
  }
};

TEST_F(BoneSourceCliTest, ABadScaleIsOneMessageInEveryCommand) {
  const std::string out = quoted(path("out"));
  expectSameRefusal(
      {"info default --scale 0", "voxelize default --voxel-size 1.2 --scale 0",
       "hierarchy default --voxel-size 1.2 --scale 0", "mesh default --voxel-size 1.2 --scale 0",
       "drill default --voxel-size 1.2 --path portal-5 --scale 0 --out-dir " + out,
       "drill default --voxel-size 1.2 --device scripted:portal-5 --scale 0 --out-dir " + out,
       "replay " + quoted(path("log.csv")) + " default --voxel-size 1.2 --scale 0 --out-dir " + out,
       "check default --scale 0", "experiment seed --scale 0 --out-dir " + out,
       "validate --quick --scale 0 --out-dir " + out},
      "osteon: error: --scale 0: must be a positive finite number");
}

TEST_F(BoneSourceCliTest, ABadVoxelSizeOrUnitIsOneMessageInEveryCommand) {
  const std::string out = quoted(path("out"));
  expectSameRefusal(
      {"voxelize default --voxel-size -1", "hierarchy default --voxel-size -1",
       "mesh default --voxel-size -1",
       "drill default --voxel-size -1 --path portal-5 --out-dir " + out,
       "replay " + quoted(path("log.csv")) + " default --voxel-size -1 --out-dir " + out},
      "osteon: error: --voxel-size -1: must be a positive number of mm");
  expectSameRefusal(
      {"info default --units furlong", "hierarchy default --voxel-size 1.2 --units furlong",
       "drill default --voxel-size 1.2 --path portal-5 --units furlong --out-dir " + out},
      "osteon: error: --units furlong: unknown unit (expected mm, cm, m or in)");
}

TEST_F(BoneSourceCliTest, AVolumesOwnVoxelSizeAndMeaningAreCheckedOnceForEveryCommand) {
  const std::string grid = path("g.nrrd");
  ASSERT_EQ(osteon("voxelize default --voxel-size 1.5 --out " + quoted(grid)).exitCode, 0);
  const std::string out = quoted(path("out"));
  const std::string csv = path("path.csv");
  test::writeBytes(csv, "t,x,y,z,drill_on\n0,0,0,200,1\n1,0,0,190,1\n");
  // The same tolerance for every command: 1.5 given as 1.5000001 is the volume's own size.
  for (const std::string& command : {"hierarchy " + quoted(grid) + " --voxel-size 1.5000001 --json",
                                     "mesh " + quoted(grid) + " --voxel-size 1.5000001 --json"}) {
    EXPECT_EQ(osteon(command).exitCode, 0) << command;
  }
  expectSameRefusal(
      {"hierarchy " + quoted(grid) + " --voxel-size 1.2",
       "mesh " + quoted(grid) + " --voxel-size 1.2",
       "drill " + quoted(grid) + " --voxel-size 1.2 --path " + quoted(csv) + " --out-dir " + out},
      "osteon: error: --voxel-size 1.2: " + grid +
          " has voxels of 1.5 mm (a volume has its own voxel size: give that, or none where the "
          "voxel "
          "size is optional)");
  expectSameRefusal(
      {"hierarchy default --voxel-size 1.2 --label 1", "mesh default --voxel-size 1.2 --label 1",
       "drill default --voxel-size 1.2 --path portal-5 --label 1 --out-dir " + out},
      "osteon: error: --label: only for a volume (.nrrd, .nhdr, .nii, .nii.gz, .mha, .mhd, DICOM); "
      "default is a mesh");
}

}  // namespace
}  // namespace osteon
