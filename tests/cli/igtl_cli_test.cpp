// `drill --igtl PORT` and `replay --igtl PORT`: the threaded run served to a client written
// with OpenIGTLink itself (tests/igtl/igtl_client.cpp), its counters in summary.json, and the
// refusals.
#include <future>

#include <nlohmann/json.hpp>

#include "igtl/igtl_client.h"
#include "support/cli_fixture.h"

namespace osteon {
namespace {

using nlohmann::json;

TEST_F(CliTest, DrillIgtlServesAThreadedRunToAClient) {
  auto client = std::async(std::launch::async, [] { return test::receiveAll(18981); });
  const CliRun run = osteon(
      "drill default --voxel-size 1.2 --levels 0 --path portal-5 --threaded "
      "--igtl 18981 --out-dir " +
      dir_ + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.err.find("serving OpenIGTLink on 127.0.0.1:18981"), std::string::npos) << run.err;
  const test::IgtlReceived got = client.get();
  const json igtl = json::parse(run.out)["runtime"]["igtl"];
  EXPECT_EQ(igtl["clients"], 1);
  EXPECT_EQ(igtl["messages_sent"], got.messages);
  EXPECT_EQ(igtl["dropped"], 0);
  EXPECT_EQ(got.wholeVolumes, 1);
  EXPECT_GT(got.subVolumes, 5);
  EXPECT_GT(got.transforms.size(), 200u);  // 100 Hz over a 7 s path
}

TEST_F(CliTest, ReplayIgtlPlaysARecordingAtItsPaceToAClient) {
  const std::string common = " --voxel-size 1.2 --levels 0 --out-dir ";
  const CliRun recorded = osteon("drill default --device scripted:portal-5 --record " +
                                 path("portal5.csv") + common + path("rec") + " --json");
  ASSERT_EQ(recorded.exitCode, 0) << recorded.err;
  auto client = std::async(std::launch::async, [] { return test::receiveAll(18983); });
  const CliRun run = osteon("replay " + path("portal5.csv") + " default --igtl 18983" + common +
                            path("replay") + " --json");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const test::IgtlReceived got = client.get();
  const json r = json::parse(run.out);
  EXPECT_EQ(r["mode"], "replay-threaded");
  EXPECT_EQ(r["runtime"]["igtl"]["clients"], 1);
  EXPECT_EQ(r["runtime"]["igtl"]["messages_sent"], got.messages);
  EXPECT_EQ(got.wholeVolumes, 1);
  EXPECT_GT(got.subVolumes, 5);
  EXPECT_GT(got.transforms.size(), 200u);  // 100 Hz over the recording's 7 s
  // Played at its pace: the client saw the run span most of the recording's length.
  EXPECT_GT(got.lastS - got.firstS, 5.0);
  // The same bone comes off as in the deterministic replay, within the threaded clock's slack.
  const double recordedMm3 = json::parse(recorded.out)["removed_volume_mm3"];
  EXPECT_NEAR(double(r["removed_volume_mm3"]), recordedMm3, 0.1 * recordedMm3);
}

TEST_F(CliTest, DrillIgtlRefusalsAreOneLine) {
  const std::string base =
      "drill default --voxel-size 1.2 --levels 0 --path portal-5 --out-dir " + dir_;
  const std::pair<const char*, const char*> cases[] = {
      {" --igtl 18982",
       "osteon: error: --igtl: only for a live run (--threaded, or a live device)\n"},
      {" --igtl-content density", "osteon: error: --igtl-content: only with --igtl PORT\n"},
      {" --threaded --igtl 18982 --igtl-content dens",
       "osteon: error: --igtl-content dens: fill or density\n"},
      {" --threaded --igtl 70000", "osteon: error: --igtl 70000: a TCP port, 1 to 65535\n"},
      {" --threaded --igtl 18982 --igtl-bind 300.1.1.1",
       "osteon: error: --igtl-bind 300.1.1.1: not an IPv4 address\n"}};
  for (const auto& [args, message] : cases) {
    const CliRun run = osteon(base + args);
    EXPECT_EQ(run.exitCode, 2) << args;
    EXPECT_EQ(run.err, message) << args;
  }
}

}  // namespace
}  // namespace osteon
