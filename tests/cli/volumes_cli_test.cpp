// Volumes as users have them (label maps and CTs, NRRD and NIfTI) through the commands that
// take a grid, and empty results that are not success (exit 1, not 0).
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "osteon/geometry/io/nrrd_io.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/bone_volumes.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/volume_files.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;
using test::TestVolume;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

// n^3 voxels of 1 mm centred on the origin; a centred cube of edge `edge` voxels holds
// `inside`, the rest `outside`; seeded Gaussian noise of `sigma` when > 0 (then rounded).
TestVolume block(int n, int edge, double inside, double outside, double sigma = 0.0,
                 unsigned seed = 1) {
  TestVolume v;
  v.sizes = {n, n, n};
  v.spacingMm = 1.0;
  v.firstCentreMm = glm::dvec3(-0.5 * (n - 1));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma > 0.0 ? sigma : 1.0);
  const int lo = (n - edge) / 2, hi = lo + edge;
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const bool in = x >= lo && x < hi && y >= lo && y < hi && z >= lo && z < hi;
        double value = in ? inside : outside;
        if (sigma > 0.0) value = std::round(value + noise(rng));
        v.values.push_back(value);
      }
    }
  }
  return v;
}

class VolumesCliTest : public CliTest {
 protected:
  nlohmann::json runJson(const std::string& args, int expectedExit = 0) const {
    const CliRun run = osteon(args);
    EXPECT_EQ(run.exitCode, expectedExit) << args << "\n" << run.err;
    if (run.out.empty()) return nlohmann::json();
    return nlohmann::json::parse(run.out);
  }
  // A CSV path straight down the z axis from z0 to z1 over `seconds`, drill on.
  std::string downPath(const std::string& name, double x, double y, double z0, double z1,
                       double seconds) const {
    std::string rows = "t,x,y,z,drill_on\n";
    rows += "0," + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z0) + ",1\n";
    rows += std::to_string(seconds) + "," + std::to_string(x) + "," + std::to_string(y) + "," +
            std::to_string(z1) + ",1\n";
    test::writeBytes(path(name), rows);
    return path(name);
  }
};

TEST_F(VolumesCliTest, ASlicerLabelMapMeshesAndSaysWhichLabelsItFound) {
  // A Slicer segmentation (uint8 voxels 0 and 1) once meshed to 0 triangles with exit 0.
  const TestVolume v = block(12, 6, 1, 0);
  test::writeTestNrrd(path("seg.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), true);
  const nlohmann::json j = runJson("mesh " + quoted(path("seg.nrrd")) + " --json");
  EXPECT_GT(j["triangles"].get<int>(), 100);
  EXPECT_EQ(j["voxels_inside"].get<int>(), 216);
  EXPECT_EQ(j["volume"]["kind"], "label map");
  EXPECT_EQ(j["volume"]["labels"], nlohmann::json({0, 1}));
  EXPECT_EQ(j["volume"]["bone_label"], "every non-zero");
  EXPECT_FALSE(j.contains("empty"));
  const CliRun text = osteon("mesh " + quoted(path("seg.nrrd")));
  EXPECT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("read as label map (labels 0 1; bone: every non-zero voxel)"),
            std::string::npos)
      << text.out;

  // Detached header, raw data.
  test::writeTestNrrd(path("det.nhdr"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false,
                      "det.raw");
  EXPECT_EQ(runJson("mesh " + quoted(path("det.nhdr")) + " --json")["voxels_inside"].get<int>(),
            216);

  // Labels 0/1/2: --label picks one, every non-zero by default.
  TestVolume three = v;
  for (int i = 0; i < 10; ++i) three.values[std::size_t(i)] = 2;
  test::writeTestNrrd(path("three.nrrd"), three, "uint8",
                      test::encodeAs<std::uint8_t>(three.values), false);
  EXPECT_EQ(runJson("mesh " + quoted(path("three.nrrd")) + " --json")["voxels_inside"].get<int>(),
            226);
  const nlohmann::json two =
      runJson("hierarchy " + quoted(path("three.nrrd")) + " --label 2 --json");
  EXPECT_EQ(two["voxels"].get<int>(), 10);
  EXPECT_EQ(two["volume"]["bone_label"].get<int>(), 2);
  EXPECT_EQ(two["volume"]["labels"], nlohmann::json({0, 1, 2}));
  expectBadInput("mesh " + quoted(path("three.nrrd")) + " --label 5", path("three.nrrd"),
                 "labels found: 0, 1, 2");
  // An iso value reads the labels as levels: bone above 1.5 is label 2's ten voxels.
  const nlohmann::json levels = runJson("mesh " + quoted(path("three.nrrd")) + " --iso 1.5 --json");
  EXPECT_EQ(levels["volume"]["kind"], "scalar");
  const CliRun above = osteon("mesh " + quoted(path("three.nrrd")) + " --iso 300 --out " +
                              quoted(path("above.ply")));
  EXPECT_EQ(above.exitCode, 1) << above.err;
  EXPECT_NE(above.err.find("empty result"), std::string::npos) << above.err;
  expectBadInput("mesh default --voxel-size 2 --label 1", "--label", "only for a volume");
}

TEST_F(VolumesCliTest, AnInt16CtInNiftiThresholdsAtTheIsoLevelItNames) {
  const TestVolume v = block(14, 8, 1100, -900, 25.0, 3);
  const std::string bytes = test::encodeAs<std::int16_t>(v.values);
  test::writeTestNifti(path("ct.nii.gz"), v, 4, 16, bytes, true);
  test::writeTestNifti(path("ct.nii"), v, 4, 16, bytes, false);
  test::writeTestNrrd(path("ct.nrrd"), v, "short", bytes, false);
  for (const char* name : {"ct.nii.gz", "ct.nii", "ct.nrrd"}) {
    SCOPED_TRACE(name);
    const nlohmann::json j = runJson("mesh " + quoted(path(name)) + " --json");
    EXPECT_EQ(j["voxels_inside"].get<int>(), 512);
    EXPECT_EQ(j["volume"]["kind"], "ct");
    EXPECT_EQ(j["volume"]["iso_hu"].get<double>(), 300.0);
    EXPECT_TRUE(j["volume"]["iso_default"].get<bool>());
    EXPECT_GT(j["triangles"].get<int>(), 100);
  }
  const CliRun text = osteon("mesh " + quoted(path("ct.nii.gz")));
  EXPECT_NE(text.out.find("iso 300 HU (default)"), std::string::npos) << text.out;
  // Above every bone value: nothing inside, which is an empty result, not success.
  const CliRun high = osteon("mesh " + quoted(path("ct.nii.gz")) + " --iso 3000 --json");
  EXPECT_EQ(high.exitCode, 1) << high.err;
  EXPECT_TRUE(nlohmann::json::parse(high.out)["empty"].get<bool>());
  EXPECT_NE(high.err.find("empty result"), std::string::npos) << high.err;
  expectBadInput("mesh " + quoted(path("ct.nii.gz")) + " --label 1", path("ct.nii.gz"),
                 "--label is for label maps");
}

TEST_F(VolumesCliTest, AVolumeThatIsNeitherIsRefusedSayingWhatWasFound) {
  TestVolume v = block(8, 4, 0, 0);
  for (std::size_t i = 0; i < v.values.size(); ++i)
    v.values[i] = double(i % 200);  // uint16, 200 values, range 199
  test::writeTestNrrd(path("odd.nrrd"), v, "uint16", test::encodeAs<std::uint16_t>(v.values),
                      false);
  expectBadInput(
      "mesh " + quoted(path("odd.nrrd")), path("odd.nrrd"),
      "neither a label map nor a CT: uint16, values 0 to 199, more than 64 distinct values");
  const TestVolume rotated = block(8, 4, 1, 0);
  test::writeTestNrrd(path("rot.nrrd"), rotated, "uint8",
                      test::encodeAs<std::uint8_t>(rotated.values), false, "",
                      "(0.7,0.7,0) (-0.7,0.7,0) (0,0,1)");
  // Rotated voxels are resampled, and the transform said.
  const nlohmann::json rot = runJson("hierarchy " + quoted(path("rot.nrrd")) + " --json");
  EXPECT_TRUE(rot["volume"]["transform"]["resampled"].get<bool>());
  EXPECT_EQ(rot["volume"]["transform"]["interpolation"], "partial volume");
}

TEST_F(VolumesCliTest, EmptyResultsExitOneUnlessAllowed) {
  const TestVolume zeros = block(8, 4, 0, 0);
  test::writeTestNrrd(path("zeros.nrrd"), zeros, "uint8",
                      test::encodeAs<std::uint8_t>(zeros.values), false);
  for (const std::string command : {"mesh", "hierarchy"}) {
    SCOPED_TRACE(command);
    const CliRun run = osteon(command + " " + quoted(path("zeros.nrrd")) + " --json");
    EXPECT_EQ(run.exitCode, 1) << run.err;
    EXPECT_NE(run.err.find("empty result"), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("zeros.nrrd"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
    const nlohmann::json j = nlohmann::json::parse(run.out);
    EXPECT_TRUE(j["empty"].get<bool>());
    EXPECT_NE(j["empty_reason"].get<std::string>().find("no voxel inside"), std::string::npos);
    const CliRun allowed =
        osteon(command + " " + quoted(path("zeros.nrrd")) + " --json --allow-empty");
    EXPECT_EQ(allowed.exitCode, 0) << allowed.err;
    EXPECT_TRUE(nlohmann::json::parse(allowed.out)["empty"].get<bool>());
    // The text output is no different in its verdict.
    EXPECT_EQ(osteon(command + " " + quoted(path("zeros.nrrd"))).exitCode, 1);
  }
  // A flat, open mesh voxelizes to nothing.
  test::writeBytes(
      path("flat.stl"),
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
      "endloop\nendfacet\nendsolid t\n");
  const CliRun vox = osteon("voxelize " + quoted(path("flat.stl")) + " --voxel-size 1 --json");
  EXPECT_EQ(vox.exitCode, 1) << vox.err;
  EXPECT_TRUE(nlohmann::json::parse(vox.out)["empty"].get<bool>());
  EXPECT_NE(vox.err.find("no voxel inside"), std::string::npos) << vox.err;
  EXPECT_EQ(
      osteon("voxelize " + quoted(path("flat.stl")) + " --voxel-size 1 --allow-empty").exitCode, 0);
  // A drill path in the air never meets bone.
  const std::string air = downPath("air.csv", 0, 0, 300, 280, 0.5);
  const CliRun drill = osteon("drill default --voxel-size 2 --levels 0 --json --path " +
                              quoted(air) + " --out-dir " + quoted(path("d")));
  EXPECT_EQ(drill.exitCode, 1) << drill.err;
  EXPECT_NE(drill.err.find("never meets bone"), std::string::npos) << drill.err;
  EXPECT_TRUE(nlohmann::json::parse(drill.out)["empty"].get<bool>());
  EXPECT_TRUE(nlohmann::json::parse(test::readBytes(path("d/summary.json")))["empty"].get<bool>());
  EXPECT_EQ(osteon("drill default --voxel-size 2 --levels 0 --allow-empty --path " + quoted(air) +
                   " --out-dir " + quoted(path("d2")))
                .exitCode,
            0);
}

// The built-in bone voxelized, then written as a label map and as a CT with noise (seeded):
// both mesh, the CT drills a CSV path and portal-5 (its head fitted to the CT's own surface).
TEST_F(VolumesCliTest, TheBuiltInBoneAsLabelMapAndCtMeshesAndDrills) {
  ASSERT_EQ(osteon("voxelize default --voxel-size 1.5 --out " + quoted(path("g.nrrd"))).exitCode,
            0);
  const geometry::VoxelGrid bone = geometry::readNrrd(path("g.nrrd")).grid;
  test::BoneVolumes made = test::boneVolumes(bone, 1.0, 30.0, 22, false);
  TestVolume& v = made.geometry;
  const std::vector<double>& labels = made.labels;
  const std::vector<double>& hu = made.hu;
  glm::ivec3 top(-1);  // the highest inside voxel: where the path goes in
  for (int z = 0; z < v.sizes.z; ++z) {
    for (int y = 0; y < v.sizes.y; ++y) {
      for (int x = 0; x < v.sizes.x; ++x) {
        if (bone.fill({x, y, z}) >= geometry::kFillHalf && z > top.z) top = {x, y, z};
      }
    }
  }
  ASSERT_GE(top.z, 0);
  v.values = labels;
  test::writeTestNrrd(path("labels.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(labels), true);
  v.values = hu;
  test::writeTestNifti(path("ct.nii.gz"), v, 4, 16, test::encodeAs<std::int16_t>(hu), true);
  const auto inside = static_cast<long long>(bone.countVoxels(geometry::kFillHalf));
  const nlohmann::json l = runJson("mesh " + quoted(path("labels.nrrd")) + " --json");
  EXPECT_EQ(l["voxels_inside"].get<long long>(), inside);
  EXPECT_EQ(l["components"].get<int>(), 1);
  const nlohmann::json c = runJson("mesh " + quoted(path("ct.nii.gz")) + " --json");
  EXPECT_NEAR(c["voxels_inside"].get<double>(), double(inside), 0.01 * double(inside));

  // Down into the bone at its top, 20 mm in 2 s.
  const glm::dvec3 entry = bone.voxelCentreMm(top);
  const std::string csv = downPath("in.csv", entry.x, entry.y, entry.z + 8.0, entry.z - 12.0, 2.0);
  const nlohmann::json d =
      runJson("drill " + quoted(path("ct.nii.gz")) + " --voxel-size 1.5 --levels 0 --json --path " +
              quoted(csv) + " --out-dir " + quoted(path("d")));
  EXPECT_GT(d["removed_volume_mm3"].get<double>(), 1.0);
  EXPECT_EQ(d["volume"]["kind"], "ct");
  EXPECT_FALSE(d.contains("empty"));
  // Portal-5 on the CT and on the mesh itself: the built-in head is dense enough that both fits
  // agree, so both portals remove about the same (the shared humerus compares the same path).
  const nlohmann::json p =
      runJson("drill " + quoted(path("ct.nii.gz")) + " --voxel-size 1.5 --levels 0 --json " +
              "--path portal-5 --out-dir " + quoted(path("p5")));
  const nlohmann::json m =
      runJson("drill default --voxel-size 1.5 --levels 0 --json --path portal-5 --out-dir " +
              quoted(path("m5")));
  const double ctMm3 = p["removed_volume_mm3"].get<double>(),
               meshMm3 = m["removed_volume_mm3"].get<double>();
  EXPECT_GT(ctMm3, 1.0);
  EXPECT_EQ(p["non_finite_forces"].get<long long>(), 0);
  EXPECT_NEAR(p["path"]["head_radius_mm"].get<double>(), m["path"]["head_radius_mm"].get<double>(),
              1.5);
  RecordProperty("ct_portal5_removed_mm3", std::to_string(ctMm3));
  RecordProperty("mesh_portal5_removed_mm3", std::to_string(meshMm3));
  EXPECT_GT(ctMm3, 0.5 * meshMm3) << "CT " << ctMm3 << " mm3, mesh " << meshMm3 << " mm3";
  EXPECT_LT(ctMm3, 2.0 * meshMm3) << "CT " << ctMm3 << " mm3, mesh " << meshMm3 << " mm3";
  expectBadInput("drill " + quoted(path("ct.nii.gz")) + " --voxel-size 1.2 --path " + quoted(csv) +
                     " --out-dir " + quoted(path("p")),
                 "--voxel-size 1.2", "has voxels of 1.5 mm");
}

// The shared humerus (metres) voxelized, then written as a label map and as an int16 CT in HU
// with partial volume and seeded noise: both drill portal-5 with the head fitted to their own
// surface, and remove what the mesh itself loses to the same path at the same voxel size.
TEST_F(VolumesCliTest, ASharedHumerusAsCtAndLabelMapDrillsPortal5LikeItsMesh) {
  const std::string stl = std::string(OSTEON_SHARED_DATA_DIR) + "/humerus_R_opensim_myosuite.stl";
  if (!fs::exists(stl)) GTEST_SKIP() << "shared data not found: " << stl;
  const std::string common = " --voxel-size 1.2 --levels 0 --json --out-dir ";
  ASSERT_EQ(osteon("voxelize " + quoted(stl) + " --units m --voxel-size 1.2 --out " +
                   quoted(path("g.nrrd")))
                .exitCode,
            0);
  const geometry::VoxelGrid bone = geometry::readNrrd(path("g.nrrd")).grid;
  test::BoneVolumes made = test::boneVolumes(bone, 1.0, 30.0, 5, true);
  TestVolume& v = made.geometry;
  const std::vector<double>& labels = made.labels;
  const std::vector<double>& hu = made.hu;
  v.values = labels;
  test::writeTestNrrd(path("labels.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(labels), true);
  v.values = hu;
  test::writeTestNrrd(path("ct.nrrd"), v, "short", test::encodeAs<std::int16_t>(hu), false);

  const nlohmann::json mesh =
      runJson("drill " + quoted(stl) + " --units m --path portal-5" + common + quoted(path("m")));
  const nlohmann::json ct = runJson("drill " + quoted(path("ct.nrrd")) +
                                    " --iso 300 --path portal-5" + common + quoted(path("c")));
  const nlohmann::json lab = runJson("drill " + quoted(path("labels.nrrd")) +
                                     " --label 1 --path portal-5" + common + quoted(path("l")));
  ASSERT_FALSE(mesh.is_null() || ct.is_null() || lab.is_null());
  EXPECT_EQ(ct["volume"]["kind"], "ct");
  EXPECT_EQ(lab["volume"]["kind"], "label map");
  const auto vec = [](const nlohmann::json& a) {
    return glm::dvec3(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
  };
  const double meshMm3 = mesh["removed_volume_mm3"].get<double>();
  RecordProperty("mesh_portal5_removed_mm3", std::to_string(meshMm3));
  for (const auto& [name, j, dir] :
       {std::make_tuple("ct", ct, "c"), std::make_tuple("labels", lab, "l")}) {
    SCOPED_TRACE(name);
    const double removedMm3 = j["removed_volume_mm3"].get<double>();
    EXPECT_GT(removedMm3, 1.0);
    EXPECT_FALSE(j.contains("empty"));
    EXPECT_EQ(j["non_finite_forces"].get<long long>(), 0);
    EXPECT_TRUE(std::isfinite(j["max_force_n"].get<double>()));
    EXPECT_GT(j["max_force_n"].get<double>(), 0.0);
    const std::string forces = test::readBytes(path(std::string(dir) + "/forces.csv"));
    EXPECT_EQ(forces.find("nan"), std::string::npos);
    EXPECT_EQ(forces.find("inf"), std::string::npos);
    // The head fitted to the volume's surface is the mesh's head, within a voxel.
    EXPECT_NEAR(j["path"]["head_radius_mm"].get<double>(),
                mesh["path"]["head_radius_mm"].get<double>(), 1.2);
    EXPECT_LT(glm::length(vec(j["path"]["head_centre_mm"]) - vec(mesh["path"]["head_centre_mm"])),
              1.2);

    // The volume's portal, its straight line read back from the first and last rows of the log,
    // drilled into the mesh: the same path into the same bone removes about the same volume.
    const std::size_t firstRow = forces.find('\n') + 1;
    const std::size_t lastRow = forces.rfind('\n', forces.size() - 2) + 1;
    const auto row = [&forces](std::size_t at) {
      std::istringstream in(forces.substr(at, forces.find('\n', at) - at));
      std::string t, x, y, z;
      std::getline(in, t, ',');
      std::getline(in, x, ',');
      std::getline(in, y, ',');
      std::getline(in, z, ',');
      return t + "," + x + "," + y + "," + z + ",1\n";
    };
    const std::string csv = path(std::string(dir) + ".csv");
    test::writeBytes(csv, "t,x,y,z,drill_on\n" + row(firstRow) + row(lastRow));
    const nlohmann::json same =
        runJson("drill " + quoted(stl) + " --units m --path " + quoted(csv) + common +
                quoted(path(std::string(dir) + "m")));
    const double sameMm3 = same["removed_volume_mm3"].get<double>();
    const double ratio = removedMm3 / sameMm3;
    RecordProperty(std::string(name) + "_portal5_removed_mm3", std::to_string(removedMm3));
    RecordProperty(std::string("mesh_on_") + name + "_portal5_removed_mm3",
                   std::to_string(sameMm3));
    EXPECT_GT(ratio, 0.5) << removedMm3 << " mm3, the mesh on the same path " << sameMm3 << " mm3";
    EXPECT_LT(ratio, 2.0) << removedMm3 << " mm3, the mesh on the same path " << sameMm3 << " mm3";
  }
}

// Dense bone wears slower: the same path into a cortical and a cancellous CT block removes less
// of the cortical one.
TEST_F(VolumesCliTest, CorticalHuWearsSlowerThanCancellous) {
  const TestVolume cortical = block(24, 16, 1300, -1000, 20.0, 7);
  const TestVolume cancellous = block(24, 16, 450, -1000, 20.0, 7);
  test::writeTestNrrd(path("cort.nrrd"), cortical, "short",
                      test::encodeAs<std::int16_t>(cortical.values), true);
  test::writeTestNrrd(path("canc.nrrd"), cancellous, "short",
                      test::encodeAs<std::int16_t>(cancellous.values), true);
  // 4 mm in 50 ms (50 steps) from just above the block's top at z = 8: cancellous voxels (15
  // steps each) wear through, cortical ones (40 steps) mostly do not.
  const std::string csv = downPath("p.csv", 0.0, 0.0, 10.0, 6.0, 0.05);
  const nlohmann::json a =
      runJson("drill " + quoted(path("cort.nrrd")) + " --voxel-size 1 --levels 0 --json --path " +
              quoted(csv) + " --out-dir " + quoted(path("a")));
  const nlohmann::json b =
      runJson("drill " + quoted(path("canc.nrrd")) + " --voxel-size 1 --levels 0 --json --path " +
              quoted(csv) + " --out-dir " + quoted(path("b")));
  const double cortRemoved = a["removed_volume_mm3"].get<double>();
  const double cancRemoved = b["removed_volume_mm3"].get<double>();
  EXPECT_GT(cancRemoved, 0.0);
  EXPECT_GT(a["max_force_n"].get<double>(), 0.0);  // the cortical block was met, not missed
  EXPECT_LT(cortRemoved, 0.8 * cancRemoved)
      << "cortical " << cortRemoved << " mm3, cancellous " << cancRemoved;
}

}  // namespace
}  // namespace osteon

namespace osteon {
namespace {

// validate takes volumes beside meshes: each at its own voxel size, its surfaces checked, and
// (no humeral head in a block) not drilled; accuracy is null, there being no source polygons.
TEST_F(VolumesCliTest, ValidateChecksAVolumeAtItsOwnVoxelSize) {
  const std::string seeds = std::string(OSTEON_SOURCE_DIR) + "/tests/data/seeds/";
  const CliRun run = osteon("validate --quick --models " + quoted(seeds + "labels.nrrd") + "," +
                            quoted(seeds + "ct.nii") + " --out-dir " + quoted(path("v")));
  ASSERT_EQ(run.exitCode, 0) << run.err << run.out;
  std::ifstream in(path("v/report.json"));
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["verdict"], "PASS");
  ASSERT_EQ(report["cases"].size(), 8u);  // 2 volumes x 1 voxel size x 2 methods x 2 modes
  for (const nlohmann::json& c : report["cases"]) {
    EXPECT_DOUBLE_EQ(c["voxel_size_mm"].get<double>(), 2.0);
    EXPECT_GT(c["triangles"].get<std::size_t>(), 0u);
    EXPECT_TRUE(c["hausdorff_mm"].is_null());
    if (c["method"] == "crackfree") {
      EXPECT_EQ(c["border_edges"].get<int>(), 0);
    }
  }
}

}  // namespace
}  // namespace osteon
