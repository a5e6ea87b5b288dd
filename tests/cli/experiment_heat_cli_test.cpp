// `osteon experiment heat`: Augustin et al. 2008's settings, the table beside the paper's
// findings (every one kept), the figure; refusals of what it cannot take, in one line.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"

namespace osteon {
namespace {

TEST_F(CliTest, TheHeatExperimentKeepsThePapersFindings) {
  const CliRun run = osteon("experiment heat --out-dir " + path("heat") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["experiment"].get<std::string>(), "heat");
  ASSERT_EQ(j["runs"].size(), 16u);
  ASSERT_EQ(j["checks"].size(), 5u);
  for (const nlohmann::json& c : j["checks"]) EXPECT_TRUE(c["pass"].get<bool>()) << c.dump();
  double hottest = 0.0;
  for (const nlohmann::json& r : j["runs"]) {
    EXPECT_LT(r["peak_irrigated_c"].get<double>(), 47.0) << r.dump();
    if (r["feed_mm_per_min"].get<double>() == 84.0)
      hottest = std::max(hottest, r["peak_c"].get<double>());
  }
  EXPECT_EQ(hottest, j["runs"][11]["peak_c"].get<double>());  // 4.5 mm at 1820 rpm
  EXPECT_NEAR(j["residuals_c"]["max"].get<double>(), 0.0, 2.0);
  for (const char* file : {"heat.md", "heat.json", "heat.png", "heat.gp", "heat.dat"})
    EXPECT_TRUE(std::filesystem::exists(path("heat/") + file)) << file;
  std::ifstream md(path("heat/heat.md"));
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("| 4.5 mm | 1820 | 84 |"), std::string::npos);
  EXPECT_EQ(text.find("FAIL"), std::string::npos);
}

TEST_F(CliTest, TheHeatExperimentRefusesAMesh) {
  expectBadInput("experiment heat --mesh " + path("bone.stl") + " --out-dir " + path("h"), "--mesh",
                 "cortical block");
}

TEST_F(CliTest, TheHeatExperimentRefusesAnOutDirThatIsAFile) {
  std::ofstream(path("file")) << "x";
  expectBadInput("experiment heat --out-dir " + path("file"), path("file"), "");
}

TEST_F(CliTest, UnknownExperimentsNameTheKnownOnes) {
  expectBadInput("experiment lunar", "experiment lunar", "seed, thrust or heat");
}

}  // namespace
}  // namespace osteon
