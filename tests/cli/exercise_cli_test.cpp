// `osteon exercise` and `osteon score` as users meet them: the plan path scores full marks,
// a bad exercise file is one line naming the file and the field.
#include <fstream>

#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"

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

}  // namespace
}  // namespace osteon
