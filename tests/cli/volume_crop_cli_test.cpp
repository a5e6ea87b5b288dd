// Volumes through the command line: --iso for any scalar volume, --crop and --crop-to-label,
// anisotropic voxels resampled at --voxel-size, and the transform reported in text and JSON.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/volume_files.h"

namespace osteon {
namespace {

using test::TestVolume;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

// 20^3 voxels of 1 mm from (0.5, 0.5, 0.5); a 10^3 cube (voxels 5..14) of `inside`.
TestVolume cube(double inside, double outside, double spread = 0.0) {
  TestVolume v;
  v.sizes = glm::ivec3(20);
  v.firstCentreMm = glm::dvec3(0.5);
  for (int z = 0; z < 20; ++z) {
    for (int y = 0; y < 20; ++y) {
      for (int x = 0; x < 20; ++x) {
        const bool in = x >= 5 && x < 15 && y >= 5 && y < 15 && z >= 5 && z < 15;
        v.values.push_back((in ? inside : outside) + spread * (x + 20 * y) / 400.0);
      }
    }
  }
  return v;
}

class VolumeCropCliTest : public CliTest {
 protected:
  nlohmann::json runJson(const std::string& args, int expectedExit = 0) const {
    const CliRun run = osteon(args);
    EXPECT_EQ(run.exitCode, expectedExit) << args << "\n" << run.err;
    return run.out.empty() ? nlohmann::json() : nlohmann::json::parse(run.out);
  }
};

TEST_F(VolumeCropCliTest, AMicroCtLoadsWithAnIsoValueInItsOwnUnits) {
  const TestVolume v = cube(160.0, 20.0, 70.0);
  test::writeTestNrrd(path("micro.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values),
                      false);
  expectBadInput("mesh " + quoted(path("micro.nrrd")), path("micro.nrrd"),
                 "--iso reads any volume as bone above that value");
  const nlohmann::json j = runJson("mesh " + quoted(path("micro.nrrd")) + " --iso 110 --json");
  EXPECT_EQ(j["volume"]["kind"], "scalar");
  EXPECT_EQ(j["volume"]["iso_value"].get<double>(), 110.0);
  EXPECT_EQ(j["voxels_inside"].get<int>(), 1000);
  const CliRun text = osteon("mesh " + quoted(path("micro.nrrd")) + " --iso 110");
  EXPECT_NE(text.out.find("read as scalar (values 20 to 211; bone above 110"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("  transform   20 x 20 x 20 voxels of 1 x 1 x 1 mm"), std::string::npos)
      << text.out;
}

TEST_F(VolumeCropCliTest, FloatMasksLoadAndAnAllZeroOneIsEmpty) {
  const TestVolume mask = cube(1.0, 0.0);
  test::writeTestNrrd(path("mask.nrrd"), mask, "double", test::encodeAs<double>(mask.values), true);
  const nlohmann::json j = runJson("mesh " + quoted(path("mask.nrrd")) + " --json");
  EXPECT_EQ(j["volume"]["kind"], "label map");
  EXPECT_EQ(j["voxels_inside"].get<int>(), 1000);
  const TestVolume zero = cube(0.0, 0.0);
  test::writeTestNrrd(path("zero.nrrd"), zero, "float", test::encodeAs<float>(zero.values), false);
  const CliRun empty = osteon("mesh " + quoted(path("zero.nrrd")));
  EXPECT_EQ(empty.exitCode, 1) << empty.err;
  EXPECT_NE(empty.err.find("empty result"), std::string::npos) << empty.err;
}

TEST_F(VolumeCropCliTest, CropsTakePartOfAVolumeAndBadOnesAreOneLine) {
  TestVolume v = cube(1.0, 0.0);
  v.values[0] = 3.0;
  test::writeTestNrrd(path("l.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false);
  const nlohmann::json box =
      runJson("mesh " + quoted(path("l.nrrd")) + " --crop 0:10,0:20,0:20 --json");
  EXPECT_TRUE(box["volume"]["transform"]["cropped"].get<bool>());
  EXPECT_EQ(box["volume"]["transform"]["sizes"], nlohmann::json({10, 20, 20}));
  EXPECT_EQ(box["voxels_inside"].get<int>(), 501);  // label 3 at voxel 0 too
  const nlohmann::json label = runJson("mesh " + quoted(path("l.nrrd")) +
                                       " --crop-to-label 1 --crop-margin 2 --label 1 --json");
  EXPECT_EQ(label["volume"]["transform"]["sizes"], nlohmann::json({14, 14, 14}));
  expectBadInput("mesh " + quoted(path("l.nrrd")) + " --crop 0:10,0:20", "--crop",
                 "needs three ranges");
  expectBadInput("mesh " + quoted(path("l.nrrd")) + " --crop 5:1,0:20,0:20", "--crop",
                 "range X '5:1' is not LOW:HIGH");
  expectBadInput("mesh " + quoted(path("l.nrrd")) + " --crop 50:60,0:20,0:20", path("l.nrrd"),
                 "the crop 50:60,0:20,0:20 mm holds no voxel of the volume");
  // An iso value reads the values as levels: no label is left to pick or crop to.
  expectBadInput("mesh " + quoted(path("l.nrrd")) + " --iso 0.5 --label 1", "--label 1",
                 "give one of them");
  expectBadInput("mesh " + quoted(path("l.nrrd")) + " --iso 0.5 --crop-to-label 1",
                 "--crop-to-label 1", "crop with --crop");
  expectBadInput("mesh " + quoted(path("l.nrrd")) + " --crop-to-label 9", path("l.nrrd"),
                 "--crop-to-label 9 is not in the label map (labels found: 0, 1, 3)");
  expectBadInput("mesh default --voxel-size 2 --crop 0:1,0:1,0:1", "--crop", "only for a volume");
}

TEST_F(VolumeCropCliTest, AnisotropicVoxelsAreResampledAtTheVoxelSizeAsked) {
  TestVolume v = cube(1000.0, -1000.0);
  test::writeTestNrrd(path("ct.nrrd"), v, "short", test::encodeAs<std::int16_t>(v.values), true, "",
                      "(1,0,0) (0,1,0) (0,0,2)");
  const nlohmann::json j = runJson("mesh " + quoted(path("ct.nrrd")) + " --json");
  const nlohmann::json& t = j["volume"]["transform"];
  EXPECT_TRUE(t["resampled"].get<bool>());
  EXPECT_EQ(t["interpolation"], "trilinear");
  EXPECT_EQ(t["spacing_mm"], nlohmann::json({1.0, 1.0, 2.0}));
  EXPECT_EQ(t["sizes"], nlohmann::json({20, 20, 40}));
  EXPECT_EQ(t["voxel_size_mm"].get<double>(), 1.0);
  const nlohmann::json half =
      runJson("mesh " + quoted(path("ct.nrrd")) + " --voxel-size 0.5 --json");
  EXPECT_EQ(half["volume"]["transform"]["sizes"], nlohmann::json({40, 40, 80}));
}

}  // namespace
}  // namespace osteon
