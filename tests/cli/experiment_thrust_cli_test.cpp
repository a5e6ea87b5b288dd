// `osteon experiment thrust`: blocks drilled under the calibrated model reproduce the published
// thrust (human cortical bone within 10 %, cancellous within 20 %), and the ratios a trainee
// should feel hold: cortical > cancellous, slow rpm > fast, fast feed > slow; the seed's model
// feels the same whatever the rpm. The table, the JSON and the figures are written together.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"

namespace osteon {
namespace {

using nlohmann::json;

TEST_F(CliTest, ExperimentThrustMatchesThePublishedThrustAndItsRatios) {
  const CliRun run = osteon("experiment thrust --json --out-dir " + path("thrust"));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json j = json::parse(run.out);
  std::map<std::string, json> byName;
  for (const json& c : j["cases"]) byName[c["name"].get<std::string>()] = c;
  const auto simulated = [&](const std::string& name) {
    EXPECT_TRUE(byName.count(name)) << name;
    return byName[name]["simulated_n"].get<double>();
  };
  for (const json& c : j["cases"]) {
    if (c["published_n"].is_null()) continue;
    const double published = c["published_n"], sim = c["simulated_n"];
    const double tolerance = c["material"] == "cortical" ? 0.10 : 0.20;
    EXPECT_NEAR(sim, published, tolerance * published) << c["name"];
    EXPECT_NEAR(c["fed_mm_per_s"].get<double>(), c["feed_mm_per_s"].get<double>(), 0.1);
    EXPECT_LT(c["device_n"].get<double>(), 3.3);  // within the device's N_max
  }
  EXPECT_GT(simulated("cortical_3.2mm_1000rpm_2mmps"),
            50.0 * simulated("cancellous_3.2mm_1000rpm_2mmps"));
  EXPECT_GT(simulated("cortical_3.2mm_1000rpm_2mmps"), simulated("cortical_3.2mm_1250rpm_2mmps"));
  EXPECT_GT(simulated("cortical_3.2mm_1250rpm_2mmps"), simulated("cortical_3.2mm_1500rpm_2mmps"));
  EXPECT_GT(simulated("cortical_3.2mm_1000rpm_2mmps"), simulated("cortical_3.2mm_1000rpm_1mmps"));
  EXPECT_GT(simulated("cortical_3.2mm_1000rpm_1mmps"), simulated("cortical_3.2mm_1000rpm_0.5mmps"));
  // The seed's model: the same push at every rpm, and cancellous as hard as cortex.
  EXPECT_NEAR(byName["cortical_3.2mm_1000rpm_2mmps"]["seed_device_n"].get<double>(),
              byName["cortical_3.2mm_1500rpm_2mmps"]["seed_device_n"].get<double>(), 0.05);
  for (const char* file : {"thrust.md", "thrust.json", "thrust.csv", "thrust.gp", "thrust.png",
                           "thrust_time.png", "runs/cortical_3.2mm_1000rpm_2mmps/forces.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(path("thrust/") + file)) << file;
  }
  const std::string header =
      test::readBytes(path("thrust/runs/cortical_3.2mm_1000rpm_2mmps/forces.csv")).substr(0, 120);
  EXPECT_EQ(header.rfind("t,px,py,pz,cx,cy,cz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level,"
                         "rpm,irrigation,removed_mm3,temperature_c\n",
                         0),
            0u)
      << header;
}

TEST_F(CliTest, ForceModelOptionsAreCheckedBeforeTheRun) {
  const std::string base = "drill default --voxel-size 1.2 --path portal-5 --out-dir " + dir_;
  const std::pair<const char*, const char*> cases[] = {
      {" --force-model real", "osteon: error: --force-model real: seed or calibrated\n"},
      {" --force-model calibrated --coupling direct",
       "osteon: error: --force-model calibrated: needs the proxy (its feed renders the bone's "
       "resistance); drop --coupling direct\n"},
      {" --rpm 10", "osteon: error: --rpm 10: revolutions per minute, 100 to 100000\n"}};
  for (const auto& [args, message] : cases) {
    const CliRun run = osteon(base + args);
    EXPECT_EQ(run.exitCode, 2) << args;
    EXPECT_EQ(run.err, message) << args;
  }
  const CliRun mesh = osteon("experiment thrust --mesh x.stl --out-dir " + dir_);
  EXPECT_EQ(mesh.exitCode, 2);
  EXPECT_NE(mesh.err.find("--mesh: experiment thrust drills blocks of its own"), std::string::npos);
}

}  // namespace
}  // namespace osteon

namespace osteon {
namespace {

// A recording carries the rpm and irrigation the run used; its replay takes them from the
// recording (not from its own --rpm) and, under the calibrated model, reproduces the forces.
TEST_F(CliTest, RecordingsCarryTheDrillSettingsAndReplaysReproduceThem) {
  const std::string common = " --voxel-size 1.2 --levels 0 --force-model calibrated --out-dir ";
  const CliRun rec = osteon(
      "drill default --device scripted:portal-5 --rpm 1500 --irrigation "
      "--record " +
      path("rec.csv") + common + path("a"));
  ASSERT_EQ(rec.exitCode, 0) << rec.err;
  const std::string recording = test::readBytes(path("rec.csv"));
  const std::size_t second = recording.find('\n') + 1;
  const std::string row = recording.substr(second, recording.find('\n', second) - second);
  EXPECT_EQ(row.substr(row.size() - 7), ",1500,1") << row;
  const CliRun replay =
      osteon("replay " + path("rec.csv") + " default --rpm 400" + common + path("b"));
  ASSERT_EQ(replay.exitCode, 0) << replay.err;
  const std::string a = test::readBytes(path("a/forces.csv")),
                    b = test::readBytes(path("b/forces.csv"));
  EXPECT_TRUE(a == b);
  EXPECT_NE(a.find(",1500,1,"), std::string::npos);
}

}  // namespace
}  // namespace osteon
