// `osteon exercise` and `osteon score` as users meet them: the plan path scores full marks,
// a bad exercise file is one line naming the file and the field.
#include <fstream>

#include <nlohmann/json.hpp>

#include "osteon/geometry/io/mesh_io.h"
#include "osteon/simulation/exercise.h"
#include "support/cli_fixture.h"
#include "support/exercise_attempts.h"
#include "support/volume_files.h"

namespace osteon {
namespace {

TEST_F(CliTest, ExercisePlanPathScoresFullMarks) {
  ASSERT_EQ(osteon("exercise plan anchor-5 --out " + path("a5.csv")).exitCode, 0);
  const CliRun run =
      osteon("score " + path("a5.csv") + " --exercise anchor-5 --json --out-dir " + path("s"));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_TRUE(j["passed"].get<bool>());
  EXPECT_DOUBLE_EQ(j["score"].get<double>(), 100.0);
  std::vector<std::string> names;
  for (const auto& c : j["criteria"]) {
    names.push_back(c["name"].get<std::string>());
    EXPECT_TRUE(c["passed"].get<bool>()) << c.dump();
    for (const char* key : {"value", "unit", "limit"}) EXPECT_TRUE(c.contains(key)) << key;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"entry", "angle", "depth", "overcut", "no_go", "force",
                                             "time"}));
  for (const char* f : {"score.json", "score.html", "score.png", "forces.csv", "summary.json"})
    EXPECT_TRUE(std::filesystem::exists(path("s/") + f)) << f;
}

TEST_F(CliTest, ExerciseListAndShow) {
  const CliRun list = osteon("exercise list");
  EXPECT_EQ(list.exitCode, 0);
  EXPECT_NE(list.out.find("anchor-7"), std::string::npos);
  const CliRun show = osteon("exercise show anchor-7 --json");
  ASSERT_EQ(show.exitCode, 0);
  EXPECT_EQ(nlohmann::json::parse(show.out)["portal"], "portal-7");
}

TEST_F(CliTest, ABadExerciseFileIsOneLineNamingTheFileAndField) {
  std::ofstream(path("bad.json")) << R"({"depth_mm": -3})";
  expectBadInput("exercise show " + path("bad.json"), path("bad.json") + ": depth_mm",
                 "positive number of mm");
  std::ofstream(path("typo.json")) << R"({"no_go": {"far_cortex": {"thicknes_mm": 2}}})";
  expectBadInput("exercise show " + path("typo.json"), "no_go.far_cortex.thicknes_mm",
                 "unknown field");
  expectBadInput("score x.csv --exercise anchor-9", "anchor-9", "no such exercise");
  expectBadInput("exercise plan anchor-5 --up q --out " + path("p.csv"), "--up q",
                 "must be x, y, z");
}

// Exit 1 (a verdict), and the criteria that failed.
std::vector<std::string> failedCriteria(const CliTest& t, const CliRun& run) {
  EXPECT_EQ(run.exitCode, 1) << run.err;
  std::vector<std::string> failed;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  for (const auto& c : j["criteria"])
    if (!c["passed"].get<bool>()) failed.push_back(c["name"].get<std::string>());
  (void)t;
  return failed;
}

TEST_F(CliTest, ScoreFailsTheThreeBadAttemptsForTheirReasons) {
  test::writeBytes(path("deep.csv"), test::attemptCsv("anchor-7", test::tenMillimetresTooDeep));
  test::writeBytes(path("tilt.csv"), test::attemptCsv("anchor-7", test::thirtyDegreesOffAxis));
  test::writeBytes(path("off.csv"), test::attemptCsv("anchor-7", test::entryFiveMillimetresOff));
  const std::string args = " --exercise anchor-7 --json --out-dir " + path("s");
  EXPECT_EQ(failedCriteria(*this, osteon("score " + path("tilt.csv") + args)),
            (std::vector<std::string>{"angle", "overcut"}));
  EXPECT_EQ(failedCriteria(*this, osteon("score " + path("off.csv") + args)),
            (std::vector<std::string>{"entry", "overcut"}));
  const CliRun deep = osteon("score " + path("deep.csv") + args);
  EXPECT_EQ(failedCriteria(*this, deep), (std::vector<std::string>{"depth", "overcut", "no_go"}));
  const nlohmann::json j = nlohmann::json::parse(deep.out);
  EXPECT_GT(j["no_go"][1]["volume_mm3"].get<double>(), 0.5);
  EXPECT_EQ(j["no_go"][1]["zone"], "far_cortex");
}

// A device recording (what `drill --device ... --record` writes) is scored as `replay` runs it:
// the recorded plan path scores as the plan path itself, and its forces are the same.
TEST_F(CliTest, ScoreTakesADeviceRecording) {
  ASSERT_EQ(osteon("exercise plan anchor-5 --out " + path("a5.csv")).exitCode, 0);
  const CliRun drill = osteon("drill default --voxel-size 1.2 --device scripted:" + path("a5.csv") +
                              " --record " + path("rec.csv") + " --out-dir " + path("d"));
  ASSERT_EQ(drill.exitCode, 0) << drill.err;
  const std::string args = " --exercise anchor-5 --json --out-dir ";
  const CliRun fromPath = osteon("score " + path("a5.csv") + args + path("p"));
  const CliRun fromRecording = osteon("score " + path("rec.csv") + args + path("r"));
  ASSERT_EQ(fromPath.exitCode, 0) << fromPath.err;
  ASSERT_EQ(fromRecording.exitCode, 0) << fromRecording.err;
  nlohmann::json p = nlohmann::json::parse(fromPath.out),
                 r = nlohmann::json::parse(fromRecording.out);
  EXPECT_DOUBLE_EQ(r["score"].get<double>(), 100.0);
  for (const char* key : {"path", "files"}) p.erase(key), r.erase(key);
  EXPECT_EQ(r, p);
  std::ifstream summary(path("r/summary.json"));
  EXPECT_EQ(nlohmann::json::parse(summary)["mode"], "replay");
  EXPECT_EQ(test::readBytes(path("r/forces.csv")), test::readBytes(path("p/forces.csv")));
  test::writeBytes(path("short.csv"), "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on\n0,1,2\n");
  expectBadInput("score " + path("short.csv") + args + path("s"), path("short.csv"), "");
  test::writeBytes(path("junk.csv"), "a,b\n1,2\n");
  expectBadInput("score " + path("junk.csv") + args + path("s"),
                 path("junk.csv") + ":1: ", "header must be a path CSV's t,x,y,z,drill_on");
}

TEST_F(CliTest, UpFindsTheBuiltInsHeadAndANonHumerusIsRefused) {
  // Given up = z the long axis is z itself, not its principal-component estimate: the same head
  // within a fraction of a millimetre.
  const std::string args = "drill default --voxel-size 1.2 --levels 0 --path portal-5 --json";
  const CliRun a = osteon(args + " --out-dir " + path("a"));
  const CliRun b = osteon(args + " --up z --out-dir " + path("b"));
  ASSERT_EQ(a.exitCode, 0) << a.err;
  ASSERT_EQ(b.exitCode, 0) << b.err;
  const nlohmann::json ja = nlohmann::json::parse(a.out)["path"];
  const nlohmann::json jb = nlohmann::json::parse(b.out)["path"];
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(ja["head_centre_mm"][std::size_t(i)].get<double>(),
                jb["head_centre_mm"][std::size_t(i)].get<double>(), 0.5);
  }
  geometry::TriangleMesh shaft = test::makeSphere(1.0, 48, 96);
  for (glm::dvec3& p : shaft.positionsMm) p *= glm::dvec3(6.0, 6.0, 60.0);
  geometry::writeMesh(shaft, path("shaft.stl"));
  expectBadInput(
      "drill " + path("shaft.stl") + " --voxel-size 1.2 --path portal-5 --out-dir " + path("c"),
      path("shaft.stl") + ": ", "--up x|y|z|-x|-y|-z) or an explicit entry point");
  expectBadInput("drill default --voxel-size 1.2 --path portal-5 --up w --out-dir " + path("c"),
                 "--up w", "must be x, y, z, -x, -y or -z");
}

TEST_F(CliTest, AnExerciseFileFindsItsBoneBesideItAndTakesAnExplicitEntryAndAxis) {
  // A box is no humerus: with an explicit entry and axis and no cartilage cap it needs none.
  std::filesystem::create_directories(path("task"));
  geometry::writeMesh(test::makeBox({0, 0, 0}, {30, 30, 30}), path("task/block.stl"));
  test::writeBytes(path("task/block.json"), R"({"bone": {"input": "block.stl", "voxel_size_mm": 1},
    "entry_mm": [15, 15, 32], "axis": {"direction": [0, 0, -1]}, "depth_mm": 10,
    "no_go": {"articular_cap": {"enabled": false}}})");
  const CliRun plan =
      osteon("exercise plan " + path("task/block.json") + " --out " + path("b.csv") + " --json");
  ASSERT_EQ(plan.exitCode, 0) << plan.err;
  const nlohmann::json j = nlohmann::json::parse(plan.out)["plan"];
  EXPECT_NEAR(j["entry_mm"][2].get<double>(), 30.0, 1e-9);
  EXPECT_FALSE(j.contains("head"));
  const CliRun score = osteon("score " + path("b.csv") + " --exercise " + path("task/block.json") +
                              " --json --out-dir " + path("s"));
  EXPECT_EQ(score.exitCode, 0) << score.err << score.out;
}

TEST_F(CliTest, AnExerciseOnALabelMapVolumeUsesTheVolumesOwnVoxelSize) {
  // 32^3 voxels of 1 mm around the origin, a 24 mm cube of label 1 in the middle.
  test::TestVolume v;
  v.sizes = {32, 32, 32};
  v.firstCentreMm = glm::dvec3(-15.5);
  for (int i = 0; i < 32 * 32 * 32; ++i) {
    const glm::ivec3 c(i % 32, (i / 32) % 32, i / (32 * 32));
    v.values.push_back(glm::all(glm::greaterThanEqual(c, glm::ivec3(4))) &&
                               glm::all(glm::lessThan(c, glm::ivec3(28)))
                           ? 1.0
                           : 0.0);
  }
  std::filesystem::create_directories(path("task"));
  test::writeTestNrrd(path("task/seg.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values),
                      true);
  const std::string rest = R"("entry_mm": [0, 0, 13], "axis": {"direction": [0, 0, -1]},
    "depth_mm": 8, "no_go": {"articular_cap": {"enabled": false}}})";
  test::writeBytes(path("task/seg.json"), R"({"bone": {"input": "seg.nrrd", "label": 1}, )" + rest);
  const CliRun plan =
      osteon("exercise plan " + path("task/seg.json") + " --out " + path("s.csv") + " --json");
  ASSERT_EQ(plan.exitCode, 0) << plan.err;
  EXPECT_NEAR(nlohmann::json::parse(plan.out)["plan"]["entry_mm"][2].get<double>(), 12.0, 0.01);
  const CliRun score = osteon("score " + path("s.csv") + " --exercise " + path("task/seg.json") +
                              " --json --out-dir " + path("out"));
  ASSERT_EQ(score.exitCode, 0) << score.err << score.out;
  const nlohmann::json j = nlohmann::json::parse(score.out);
  EXPECT_DOUBLE_EQ(j["score"].get<double>(), 100.0);
  EXPECT_NEAR(j["depth_mm"].get<double>(), 8.0, 1.0);
  std::ifstream summary(path("out/summary.json"));
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(summary)["voxel_size_mm"].get<double>(), 1.0);
  // A voxel size the volume does not have is refused naming the exercise's field.
  test::writeBytes(path("task/seg2.json"),
                   R"({"bone": {"input": "seg.nrrd", "label": 1, "voxel_size_mm": 2}, )" + rest);
  expectBadInput("score " + path("s.csv") + " --exercise " + path("task/seg2.json") +
                     " --out-dir " + path("out2"),
                 path("task/seg2.json") + ": bone.voxel_size_mm 2: ", "has voxels of 1 mm");
}

}  // namespace
}  // namespace osteon
