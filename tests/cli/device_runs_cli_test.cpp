// Device runs on the command line where they used to crash, hang or lose without a word: a
// SpaceMouse path that is no HID device (hidapi crashed), a recording stamped at Unix time
// replayed through the threaded runtime (it ran until its absolute last stamp), runs that never
// meet bone through a device or a recording (exit 0 where --path gives 1), and a board monitored
// at 115,200 baud (events dropped from a full queue, silently).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"
#include "support/cli_processes.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

using nlohmann::json;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// Recordings without the drill's settings (as osteon wrote them before), and with them.
const char* kRecordingHeader = "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on\n";
const char* kRecordingHeaderWithSettings =
    "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on,rpm,irrigation\n";

// A recording of `rows` 1 ms rows from startS, the tool held at z (world mm) with the drill on.
std::string recordingAt(double startS, int rows, double zMm) {
  std::string text = kRecordingHeader;
  char row[160];
  for (int i = 0; i < rows; ++i) {
    std::snprintf(row, sizeof row, "%.6f,0,0,%.3f,1,0,0,0,1,0,1\n", startS + 0.001 * i, zMm);
    text += row;
  }
  return text;
}

TEST_F(CliTest, ASpaceMousePathThatIsNoHidDeviceIsExit2NotACrash) {
  const std::string fifo = path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  test::writeBytes(path("report.bin"), "not a device\n");
  expectBadInput("devices monitor spacemouse:/dev/null --duration 1", "spacemouse:/dev/null",
                 "not a HID device");
  expectBadInput("devices monitor spacemouse:" + fifo + " --duration 1", fifo,
                 "not a HID device (a FIFO)");
  expectBadInput("devices monitor spacemouse:" + path("report.bin") + " --duration 1",
                 path("report.bin"), "not a HID device (a regular file)");
  expectBadInput(
      "drill default --voxel-size 1.2 --device spacemouse:/dev/null --duration 1 --out-dir " +
          quoted(path("o")),
      "spacemouse:/dev/null", "not a HID device");
  EXPECT_FALSE(std::filesystem::exists(path("o/forces.csv")));
}

TEST_F(CliTest, AThreadedReplayOfARecordingStampedAtUnixTimeRunsForItsLength) {
  // A descent into the humeral head (its top is near (5.6, 2.6, 49) mm), recorded, then
  // stamped from 1.7e9 s (Unix time).
  test::writeBytes(path("p.csv"), "t,x,y,z,drill_on\n0,5.6,2.6,60,1\n0.5,5.6,2.6,40,1\n");
  const CliRun rec = osteon(
      "drill default --voxel-size 1.2 --levels 0 --tool burr --device scripted:" + path("p.csv") +
      " --record " + quoted(path("rec.csv")) + " --out-dir " + quoted(path("a")));
  ASSERT_EQ(rec.exitCode, 0) << rec.err;
  std::string shifted = kRecordingHeaderWithSettings;
  int rows = 0;
  for (const std::string& line : splitLines(test::readBytes(path("rec.csv")))) {
    if (rows++ == 0) continue;
    const std::size_t comma = line.find(',');
    char t[64];
    std::snprintf(t, sizeof t, "%.6f", 1.7e9 + std::stod(line.substr(0, comma)));
    shifted += t + line.substr(comma) + "\n";
  }
  ASSERT_GT(rows, 400);
  test::writeBytes(path("unix.csv"), shifted);

  const auto start = std::chrono::steady_clock::now();
  const CliRun live =
      osteon("drill default --voxel-size 1.2 --levels 0 --tool burr --threaded --device replay:" +
             path("unix.csv") + " --json --out-dir " + quoted(path("b")));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(live.exitCode, 0) << live.err;
  EXPECT_LT(seconds, 20.0);  // a 0.5 s recording (it used to run until t = 1.7e9 s)
  const json j = json::parse(live.out);
  EXPECT_NEAR(j["device"]["duration_s"].get<double>(), 0.5, 1e-6);
  // Its poses reached the bone: the recording's clock was lined up with the run's.
  EXPECT_GT(j["removed_volume_mm3"].get<double>(), 0.0);
  EXPECT_LE(j["safety"]["max_force_n"].get<double>(), 3.3);
}

TEST_F(CliTest, RunsThatNeverMeetBoneAreEmptyWhateverDrivesThem) {
  test::writeBytes(path("air.csv"), "t,x,y,z,drill_on\n0,0,0,500,1\n0.2,0,0,490,1\n");
  test::writeBytes(path("air_rec.csv"), recordingAt(0.0, 200, 500.0));
  const std::string tail = " --voxel-size 1.2 --levels 0 --out-dir ";
  struct Case {
    std::string name, args;
  };
  for (const Case& c :
       {Case{"path", "drill default --path " + path("air.csv") + tail + quoted(path("o1"))},
        Case{"scripted",
             "drill default --device scripted:" + path("air.csv") + tail + quoted(path("o2"))},
        Case{"replay device",
             "drill default --device replay:" + path("air_rec.csv") + tail + quoted(path("o3"))},
        Case{"replay",
             "replay " + quoted(path("air_rec.csv")) + " default" + tail + quoted(path("o4"))}}) {
    const CliRun run = osteon(c.args + " --json");
    EXPECT_EQ(run.exitCode, 1) << c.name << ": " << run.err;
    EXPECT_NE(run.err.find("empty result: the path never meets bone"), std::string::npos)
        << c.name << ": " << run.err;
    ASSERT_FALSE(run.out.empty()) << c.name;
    const json j = json::parse(run.out);
    EXPECT_EQ(j["empty"], true) << c.name;
    EXPECT_EQ(j["removed_volume_mm3"], 0.0) << c.name;
    const CliRun allowed = osteon(c.args + " --allow-empty --json");
    EXPECT_EQ(allowed.exitCode, 0) << c.name << ": " << allowed.err;
    EXPECT_NE(allowed.err.find("accepted: --allow-empty"), std::string::npos)
        << c.name << ": " << allowed.err;
    EXPECT_EQ(json::parse(allowed.out)["empty"], true) << c.name;
  }
}

// A board at 115,200 baud: N lines as fast as the line rate allows, every one printed while the
// monitor's output is read as it comes, and the last line says none was dropped.
TEST_F(CliTest, DevicesMonitorKeepsUpWithABoardAt115200Baud) {
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  constexpr int kLines = 6000;
  RunningOsteon monitor({"devices", "monitor", "serial:" + board.slavePath + "@115200", "--count",
                         std::to_string(kLines), "--json"},
                        path("monitor.err"));
  std::thread writer([&board] {
    // 11,520 bytes a second (8N1: 10 bits a byte), in 10 ms slices.
    std::string slice;
    const auto start = std::chrono::steady_clock::now();
    std::size_t sent = 0;
    for (int i = 0; i < kLines; ++i) {
      slice += "B=" + std::to_string(i % 16) + ",P=" + std::to_string(i % 1024) + "\n";
      const double dueS = double(sent + slice.size()) / 11520.0;
      if (slice.size() >= 115 || i + 1 == kLines) {
        std::this_thread::sleep_until(
            start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(dueS)));
        if (!board.write(slice)) return;
        sent += slice.size();
        slice.clear();
      }
    }
  });
  int seen = 0;
  for (; seen < kLines; ++seen) {
    const std::string line = monitor.nextLine();
    if (line.empty()) break;
    const json e = json::parse(line);
    if (e.contains("status")) {
      ADD_FAILURE() << "event " << seen << " is " << line;
      break;
    }
    ASSERT_EQ(e["pedal"], seen % 1024) << line;
  }
  writer.join();
  EXPECT_EQ(seen, kLines) << test::readBytes(path("monitor.err"));
  const std::string last = monitor.nextLine();
  ASSERT_FALSE(last.empty());
  const json end = json::parse(last);
  EXPECT_EQ(end["status"], "ended");
  EXPECT_EQ(end["events"], kLines);
  EXPECT_EQ(end["events_dropped"], 0);
  EXPECT_EQ(monitor.waitExit(), 0);
  EXPECT_EQ(test::readBytes(path("monitor.err")), "");
}

// A consumer that stops reading: the board's queue fills and events are lost, which the
// monitor now says (a line in the stream, the count at the end, a warning on stderr).
TEST_F(CliTest, DevicesMonitorReportsEventsItDropped) {
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  RunningOsteon monitor(
      {"devices", "monitor", "serial:" + board.slavePath, "--duration", "4", "--json"},
      path("monitor.err"));
  std::string lines;
  constexpr int kLines = 20000;
  for (int i = 0; i < kLines; ++i) lines += "B=1,P=" + std::to_string(i % 1024) + "\n";
  ASSERT_TRUE(board.write(lines));  // nobody reads the monitor's output meanwhile
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  int printed = 0;
  json dropLine, end;
  for (std::string line = monitor.nextLine(); !line.empty(); line = monitor.nextLine()) {
    const json e = json::parse(line);
    const std::string status = e.value("status", "");
    if (status == "dropped") {
      if (dropLine.is_null()) dropLine = e;
    } else if (status == "ended") {
      end = e;
    } else {
      ++printed;  // a board line, or the board falling silent once the lines have come
    }
  }
  EXPECT_EQ(monitor.waitExit(), 0);
  ASSERT_FALSE(end.is_null());
  ASSERT_FALSE(dropLine.is_null());
  EXPECT_GT(end["events_dropped"].get<int>(), 0);
  EXPECT_EQ(end["events"], printed);
  // Every line either printed or counted (and the one "disconnected" once the board fell silent).
  EXPECT_GE(printed + end["events_dropped"].get<int>(), kLines);
  EXPECT_LE(printed + end["events_dropped"].get<int>(), kLines + 1);
  const std::string err = test::readBytes(path("monitor.err"));
  EXPECT_NE(err.find("events dropped: the monitor fell behind"), std::string::npos) << err;
  EXPECT_NE(err.find(std::to_string(end["events_dropped"].get<int>()) + " events dropped"),
            std::string::npos)
      << err;
}

}  // namespace
}  // namespace osteon
