// Devices on the command line: `devices list` (none here), `devices monitor` decoding a board on
// a pseudo-terminal as it runs, `drill --device` and `--record`, and `replay`: a recorded
// portal-5 replays to drill's forces.csv byte for byte, a log with every fault kind is survived
// and counted, and files that are not recordings are exit 2 with one line.
#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <poll.h>
#include <pty.h>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <termios.h>
#include <thread>
#include <unistd.h>
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

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

TEST_F(CliTest, DevicesListFindsNoneHereAndSucceeds) {
  const CliRun run = osteon("devices list --json");
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json j = json::parse(run.out);
  ASSERT_TRUE(j["devices"].is_array());
  EXPECT_TRUE(j["devices"].empty()) << run.out;
  EXPECT_EQ(j["serial_listing"], true);
  EXPECT_EQ(j["touch_built_in"], false);
  const CliRun text = osteon("devices list");
  EXPECT_EQ(text.exitCode, 0);
  EXPECT_NE(text.out.find("no devices attached"), std::string::npos) << text.out;
  EXPECT_TRUE(text.err.empty()) << text.err;
}

TEST_F(CliTest, DevicesMonitorDecodesABoardOnAPseudoTerminal) {
  const std::string link = path("ttyBoard");
  auto board = std::make_unique<test::FakeBoard>();
  ASSERT_TRUE(board->open());
  test::pointLink(link, board->slavePath);
  RunningOsteon monitor({"devices", "monitor", "serial:" + link, "--count", "8", "--json"},
                        path("monitor.err"));

  ASSERT_TRUE(board->write("B=5,P=512\n"));
  ASSERT_TRUE(board->write(std::string("\x01\xfe\xff garbage", 12) + "\n"));
  ASSERT_TRUE(board->write("B=zz,P=1\n"));
  ASSERT_TRUE(
      board->write(std::string(100 * 1024, 'A') + "\n"));  // 100 kB: dropped as it streams in
  ASSERT_TRUE(board->write("B=1f,P=0,K=-3,X=9\r\n"));
  std::vector<json> events;
  for (int i = 0; i < 5; ++i) {
    const std::string line = monitor.nextLine();
    ASSERT_FALSE(line.empty()) << "event " << i
                               << "; stderr: " << test::readBytes(path("monitor.err"));
    events.push_back(json::parse(line));
  }
  EXPECT_EQ(events[0]["buttons"], 5);
  EXPECT_EQ(events[0]["pedal"], 512);
  EXPECT_EQ(events[0]["knob"], 0);
  EXPECT_TRUE(events[0].contains("t"));
  EXPECT_NE(events[1]["error"].get<std::string>().find("printable ASCII"), std::string::npos);
  EXPECT_NE(events[2]["error"].get<std::string>().find("B is not a hex button mask"),
            std::string::npos);
  EXPECT_EQ(events[3]["error"], "line longer than 256 bytes");
  EXPECT_EQ(events[4]["buttons"], 31);
  EXPECT_EQ(events[4]["knob"], -3);

  // Unplugged: disconnected at once. Plugged back in (a new terminal behind the same name).
  board->unplug();
  const std::string gone = monitor.nextLine();
  ASSERT_FALSE(gone.empty());
  EXPECT_EQ(json::parse(gone)["status"], "disconnected");
  board = std::make_unique<test::FakeBoard>();
  ASSERT_TRUE(board->open());
  test::pointLink(link, board->slavePath);
  ASSERT_TRUE(board->write("B=2,P=1023\n"));
  const std::string back = monitor.nextLine();
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(json::parse(back)["status"], "connected");
  const std::string last = monitor.nextLine();
  ASSERT_FALSE(last.empty());
  EXPECT_EQ(json::parse(last)["pedal"], 1023);
  EXPECT_EQ(monitor.waitExit(), 0) << test::readBytes(path("monitor.err"));  // after 8 events
}

TEST_F(CliTest, DevicesMonitorTextAndItsLimits) {
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  ASSERT_TRUE(board.write("B=3,P=7\n"));
  const CliRun run = osteon("devices monitor serial:" + board.slavePath + "@115200 --count 1");
  EXPECT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("buttons=0x3 pedal=7 knob=0"), std::string::npos) << run.out;
  // A board that says nothing: --duration ends the watch, exit 0.
  const auto start = std::chrono::steady_clock::now();
  const CliRun quiet = osteon("devices monitor serial:" + board.slavePath + " --duration 0.3");
  EXPECT_EQ(quiet.exitCode, 0) << quiet.err;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  expectBadInput("devices monitor serial:" + path("ttyNone") + " --count 1",
                 "serial:" + path("ttyNone"), "cannot open");
  expectBadInput("devices monitor serial:" + board.slavePath + " --count 0", "--count 0",
                 "at least 1");
  expectBadInput("devices monitor serial:" + board.slavePath + "@1234 --count 1", "@1234",
                 "not a standard rate");
  expectBadInput("devices monitor scripted:portal-5 --count 1", "scripted:portal-5", "session");
  expectBadInput("devices monitor joystick --count 1", "joystick", "unknown device");
  expectBadInput("devices monitor mouse --count 1", "mouse", "viewer");
  expectBadInput("devices monitor spacemouse --count 1", "spacemouse",
                 "no 3Dconnexion device attached");
  expectBadInput("devices monitor touch --count 1", "touch", "built without OpenHaptics");
  const CliRun none = osteon("devices");
  EXPECT_EQ(none.exitCode, 2);
}

// drill --path portal-5, the scripted portal-5 device recorded at 1 kHz, and its recording
// replayed: the same forces.csv, byte for byte.
TEST_F(CliTest, ARecordedPortal5ReplaysToDrillsForcesByteForByte) {
  const std::string common = " --voxel-size 1.2 --levels 2 --json --out-dir ";
  const CliRun drill = osteon("drill default --path portal-5" + common + quoted(path("drill")));
  ASSERT_EQ(drill.exitCode, 0) << drill.err;
  // Devices and recordings default to proxy coupling; the portal path is direct.
  const CliRun scripted =
      osteon("drill default --device scripted:portal-5 --coupling direct --record " +
             quoted(path("portal5.csv")) + common + quoted(path("scripted")));
  ASSERT_EQ(scripted.exitCode, 0) << scripted.err;
  const CliRun replay = osteon("replay " + quoted(path("portal5.csv")) +
                               " default --coupling direct" + common + quoted(path("replay")));
  ASSERT_EQ(replay.exitCode, 0) << replay.err;

  const std::string forces = test::readBytes(path("drill/forces.csv"));
  ASSERT_EQ(lines(forces).size(), 7002u);
  EXPECT_TRUE(forces == test::readBytes(path("scripted/forces.csv")));
  EXPECT_TRUE(forces == test::readBytes(path("replay/forces.csv")));
  const std::vector<std::string> recording = lines(test::readBytes(path("portal5.csv")));
  ASSERT_EQ(recording.size(), 7002u);  // a row per ms from 0 to 7 s, and the header
  EXPECT_EQ(recording[0], "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on,rpm,irrigation");

  const json d = json::parse(drill.out), r = json::parse(replay.out), s = json::parse(scripted.out);
  for (const char* key :
       {"steps", "max_force_n", "jitter_n", "max_step_change_n", "removed_volume_mm3"}) {
    EXPECT_EQ(r[key], d[key]) << key;
    EXPECT_EQ(s[key], d[key]) << key;
  }
  EXPECT_EQ(r["mode"], "replay");
  EXPECT_EQ(r["faults"], (json{{"nan", 0}, {"gaps", 0}, {"jumps", 0}, {"watchdog", 0}}));
  EXPECT_EQ(r["safety"]["clamped_steps"], 0);
  EXPECT_EQ(r["safety"]["ramp_steps"], 500);  // the first half second
  EXPECT_EQ(r["recording"]["rows"], 7001);
  EXPECT_EQ(s["device"]["recorded_rows"], 7001);
  EXPECT_EQ(s["files"]["recording"], path("portal5.csv"));
  EXPECT_TRUE(std::filesystem::exists(path("replay/surface.ply")));
  EXPECT_EQ(json::parse(test::readBytes(path("replay/summary.json")))["faults"], r["faults"]);
}

TEST_F(CliTest, ReplaySurvivesALogWithEveryFaultKindAndCountsEach) {
  ASSERT_EQ(
      osteon("drill default --device scripted:portal-5 --voxel-size 1.2 --levels 0 --record " +
             quoted(path("clean.csv")) + " --out-dir " + quoted(path("rec")))
          .exitCode,
      0);
  // The recording with a NaN at 2 s, a 20 ms gap at 3 s, a 30 mm jump at 3.5 s and a stalled
  // recording loop at 4 s (rows 3 ms apart for 30 ms).
  std::ostringstream faulty;
  int row = -1;
  for (const std::string& line : lines(test::readBytes(path("clean.csv")))) {
    if (row++ < 0) {
      faulty << line << "\n";
      continue;
    }
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
    const int ms = row - 1;
    if (ms > 3000 && ms <= 3020) continue;
    if (ms > 4000 && ms < 4030 && ms % 3 != 0) continue;
    if (ms == 2000) f[2] = "nan";
    if (ms == 3500) f[3] = std::to_string(std::stod(f[3]) + 30.0);
    for (std::size_t i = 0; i < f.size(); ++i) faulty << (i ? "," : "") << f[i];
    faulty << "\n";
  }
  test::writeBytes(path("faulty.csv"), faulty.str());
  const CliRun run =
      osteon("replay " + quoted(path("faulty.csv")) +
             " default --voxel-size 1.2 --levels 0 --json --out-dir " + quoted(path("out")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const json j = json::parse(run.out);
  EXPECT_EQ(j["faults"], (json{{"nan", 1}, {"gaps", 1}, {"jumps", 1}, {"watchdog", 1}}));
  EXPECT_EQ(j["steps"], 7001);
  EXPECT_LE(j["safety"]["max_force_n"].get<double>(), 3.3);
  EXPECT_GT(j["safety"]["held_steps"].get<int>(), 0);
  EXPECT_GT(j["safety"]["ramp_steps"].get<int>(), 500);
  // The session never saw the faulty poses: no NaN and no 30 mm excursion in the force log.
  double previousZ = 0.0;
  int n = 0;
  for (const std::string& line : lines(test::readBytes(path("out/forces.csv")))) {
    if (n++ == 0) continue;
    EXPECT_EQ(line.find("nan"), std::string::npos) << line;
    std::istringstream fields(line);
    std::string t, x, y, z;
    std::getline(fields, t, ',');
    std::getline(fields, x, ',');
    std::getline(fields, y, ',');
    std::getline(fields, z, ',');
    if (n > 2) {
      EXPECT_LT(std::abs(std::stod(z) - previousZ), 1.0) << line;
    }
    previousZ = std::stod(z);
  }
  EXPECT_EQ(n, 7002);
}

TEST_F(CliTest, ReplayRefusesFilesThatAreNotRecordings) {
  const std::string header = "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on\n";
  test::writeBytes(path("path.csv"), "t,x,y,z,drill_on\n0,0,0,80,1\n1,0,0,60,1\n");
  test::writeBytes(path("binary.csv"), std::string("\x7f"
                                                   "ELF\x02\x01\x01\0\0\0",
                                                   10));
  test::writeBytes(path("fields.csv"), header + "0,1,2\n");
  test::writeBytes(path("text.csv"),
                   header + "0,1,2,3,1,0,0,0,0,0,1\n0.001,1,2,3,one,0,0,0,0,0,1\n");
  test::writeBytes(path("back.csv"), header + "0.5,1,2,3,1,0,0,0,0,0,1\n0.2,1,2,3,1,0,0,0,0,0,1\n");
  const std::string tail = " default --voxel-size 1.2 --out-dir " + quoted(path("o"));
  expectBadInput("replay " + quoted(path("path.csv")) + tail, path("path.csv") + ":1",
                 "not a device recording");
  expectBadInput("replay " + quoted(path("binary.csv")) + tail, path("binary.csv") + ":1",
                 "not a device recording");
  expectBadInput("replay " + quoted(path("fields.csv")) + tail, path("fields.csv") + ":2",
                 "expected 11 fields");
  expectBadInput("replay " + quoted(path("text.csv")) + tail, path("text.csv") + ":3",
                 "qw 'one' is not a number");
  expectBadInput("replay " + quoted(path("back.csv")) + tail, path("back.csv") + ":3",
                 "is not after");
  expectBadInput("replay " + quoted(path("none.csv")) + tail, path("none.csv"), "cannot open");
  expectBadInput("replay " + quoted(path("path.csv")) + " default --voxel-size 0", "--voxel-size 0",
                 "positive");
  EXPECT_FALSE(std::filesystem::exists(path("o/forces.csv")));
  // Outputs that are inputs are refused before any work.
  std::filesystem::create_directories(path("o"));
  test::writeBytes(path("o/forces.csv"), header + "0,1,2,3,1,0,0,0,0,0,1\n");
  expectBadInput("replay " + quoted(path("o/forces.csv")) + tail, "forces.csv",
                 "the same file as the input");
  EXPECT_EQ(lines(test::readBytes(path("o/forces.csv"))).size(), 2u);
}

TEST_F(CliTest, DrillWithADeviceRefusesWhatCannotDriveIt) {
  const std::string tail = " --voxel-size 1.2 --out-dir " + quoted(path("o"));
  expectBadInput("drill default --device joystick" + tail, "joystick", "unknown device");
  expectBadInput("drill default --device mouse" + tail, "mouse", "viewer");
  expectBadInput("drill default --device spacemouse --duration 1" + tail, "spacemouse",
                 "no 3Dconnexion device attached");
  expectBadInput("drill default --device touch --duration 1" + tail, "touch",
                 "built without OpenHaptics");
  expectBadInput("drill default --device serial:" + path("ttyNone") + " --duration 1" + tail,
                 "serial:", "cannot open");
  expectBadInput("drill default --device replay:" + path("none.csv") + tail, path("none.csv"),
                 "cannot open");
  expectBadInput("drill default --device scripted:portal-6" + tail, "portal-6", "not a portal");
  expectBadInput("drill default --device scripted:portal-5 --duration 2" + tail, "--duration",
                 "live devices");
  expectBadInput("drill default --device scripted:portal-5 --duration -1" + tail, "--duration -1",
                 "seconds");
  expectBadInput("drill default --device scripted:portal-5 --path portal-5" + tail, "--device",
                 "excludes");
  expectBadInput("drill default" + tail, "--path or --device", "required");
  expectBadInput("drill default --path portal-5 --record " + quoted(path("r.csv")) + tail,
                 "--record", "only with --device");
  // A board gives no pose: it cannot drive the tool alone.
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  expectBadInput("drill default --device serial:" + board.slavePath + " --duration 1" + tail,
                 "serial:" + board.slavePath, "gives no pose");
  // A live device needs --duration.
  test::writeBytes(path("p.csv"), "t,x,y,z,drill_on\n0,0,0,80,1\n1,0,0,60,1\n");
  // Recording over an input is refused before the run.
  expectBadInput("drill default --device scripted:" + path("p.csv") + " --record " +
                     quoted(path("p.csv")) + tail,
                 "--record", "input");
  EXPECT_EQ(lines(test::readBytes(path("p.csv"))).size(), 3u);
  expectBadInput("drill default --device scripted:" + path("p.csv") + " --record " +
                     quoted(path("o/forces.csv")) + tail,
                 "--record", "forces.csv");
}

TEST_F(CliTest, DrillWithAScriptedCsvAndARecordingReplayedLive) {
  // A drill path CSV as a device (down into the humeral head), recorded; its recording driven
  // through the threaded runtime.
  test::writeBytes(path("p.csv"), "t,x,y,z,drill_on\n0,5.6,2.6,60,1\n0.5,5.6,2.6,40,1\n");
  const CliRun scripted = osteon(
      "drill default --voxel-size 1.2 --levels 0 --tool burr --device scripted:" + path("p.csv") +
      " --record " + quoted(path("p_rec.csv")) + " --json --out-dir " + quoted(path("a")));
  ASSERT_EQ(scripted.exitCode, 0) << scripted.err;
  EXPECT_EQ(json::parse(scripted.out)["steps"], 501);
  const CliRun live =
      osteon("drill default --voxel-size 1.2 --levels 0 --tool burr --threaded --device replay:" +
             path("p_rec.csv") + " --json --out-dir " + quoted(path("b")));
  ASSERT_EQ(live.exitCode, 0) << live.err;
  const json j = json::parse(live.out);
  EXPECT_EQ(j["mode"], "device-threaded");
  EXPECT_GT(j["runtime"]["haptic_steps"].get<int>(), 250);
  EXPECT_LE(j["safety"]["max_force_n"].get<double>(), 3.3);
}

}  // namespace
}  // namespace osteon
