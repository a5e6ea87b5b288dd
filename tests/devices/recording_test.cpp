// Recording and replay: rows read back bit for bit, non-finite poses kept as the faults they
// were, the file flushed every 100 ms while recording, files that are not recordings refused
// with their line, and the replay device's clock.
#include "osteon/devices/recording.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "support/files.h"
#include "support/serial_board.h"

namespace osteon::devices {
namespace {

class RecordingTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("recording");
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }
};

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST_F(RecordingTest, RowsReadBackBitForBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> any(-500.0, 500.0);
  std::vector<std::pair<double, DeviceSample>> written;
  {
    StreamRecorder recorder(path("log.csv"));
    for (int i = 0; i < 3000; ++i) {
      DeviceSample s;
      const double t = 0.001 * i;
      s.positionMm = glm::dvec3(any(rng), any(rng), any(rng) * 1e-7);
      s.orientation = glm::normalize(glm::dquat(any(rng), any(rng), any(rng), any(rng)));
      s.buttons = std::uint32_t(rng());
      s.pedal = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
      s.drillOn = i % 3 == 0;
      if (i == 2000) s.positionMm.y = std::numeric_limits<double>::quiet_NaN();
      if (i == 2001) s.orientation.w = -std::numeric_limits<double>::infinity();
      if (i == 2002) s.positionMm.x = -0.0;
      recorder.record(t, s);
      written.emplace_back(t, s);
    }
    recorder.close();
    EXPECT_EQ(recorder.rows(), 3000u);
    EXPECT_EQ(recorder.dropped(), 0u);
  }
  const std::string text = test::readBytes(path("log.csv"));
  EXPECT_EQ(text.substr(0, text.find('\n')), kRecordingHeader);
  const Recording r = loadRecording(path("log.csv"));
  ASSERT_EQ(r.rows.size(), written.size());
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const RecordingRow& row = r.rows[i];
    const DeviceSample& s = written[i].second;
    ASSERT_TRUE(sameBits(row.tS, written[i].first)) << i;
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(sameBits(row.positionMm[k], s.positionMm[k]) ||
                  (std::isnan(row.positionMm[k]) && std::isnan(s.positionMm[k])))
          << i;
    }
    ASSERT_TRUE(sameBits(row.orientation.w, s.orientation.w)) << i;
    ASSERT_TRUE(sameBits(row.orientation.z, s.orientation.z)) << i;
    ASSERT_EQ(row.buttons, s.buttons);
    ASSERT_TRUE(sameBits(row.pedal, s.pedal));
    ASSERT_EQ(row.drillOn, s.drillOn);
  }
  EXPECT_TRUE(std::isnan(r.rows[2000].positionMm.y));
  EXPECT_EQ(r.rows[2001].orientation.w, -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::signbit(r.rows[2002].positionMm.x));
}

TEST_F(RecordingTest, TheFileIsFlushedEvery100msWhileRecording) {
  StreamRecorder recorder(path("live.csv"));
  DeviceSample s;
  const auto start = std::chrono::steady_clock::now();
  std::size_t largestGapBytes = 0;
  std::uintmax_t lastSize = 0;
  auto lastGrowth = start;
  double longestWaitS = 0.0;
  // 600 ms of a 1 kHz loop; the file must grow at least every ~100 ms.
  for (int i = 0; i < 600; ++i) {
    recorder.record(0.001 * i, s);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const std::uintmax_t size = std::filesystem::file_size(path("live.csv"));
    const auto now = std::chrono::steady_clock::now();
    if (size != lastSize) {
      largestGapBytes = std::max<std::size_t>(largestGapBytes, std::size_t(size - lastSize));
      lastSize = size;
      lastGrowth = now;
    }
    longestWaitS = std::max(longestWaitS, std::chrono::duration<double>(now - lastGrowth).count());
  }
  EXPECT_LT(longestWaitS, 0.3);  // 100 ms, with room for a busy machine
  EXPECT_GT(lastSize, 0u);
  recorder.close();
  EXPECT_EQ(loadRecording(path("live.csv")).rows.size(), 600u);
}

TEST_F(RecordingTest, ALiveLoopDropsRowsRatherThanWaitWhenTheBufferIsFull) {
  RecorderOptions options;
  options.bufferBytes = 4096;  // a few dozen rows
  options.flushEveryS = 10.0;  // the writer sleeps through the burst
  StreamRecorder recorder(path("small.csv"), options);
  DeviceSample s;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 1000; ++i) recorder.record(0.001 * i, s);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_GT(recorder.dropped(), 0u);
  EXPECT_EQ(recorder.rows() + recorder.dropped(), 1000u);
  recorder.close();
  EXPECT_EQ(loadRecording(path("small.csv")).rows.size(), recorder.rows());

  options.waitWhenFull = true;  // a deterministic run waits instead, and keeps every row
  StreamRecorder waiting(path("all.csv"), options);
  for (int i = 0; i < 1000; ++i) waiting.record(0.001 * i, s);
  waiting.close();
  EXPECT_EQ(waiting.dropped(), 0u);
  EXPECT_EQ(loadRecording(path("all.csv")).rows.size(), 1000u);
}

TEST_F(RecordingTest, FilesThatAreNotRecordingsAreRefusedWithTheirLine) {
  // Recordings without the drill's settings (as osteon wrote them before) keep their checks.
  const std::string header = std::string(kRecordingHeaderWithoutSettings) + "\n";
  const std::string withSettings = std::string(kRecordingHeader) + "\n";
  const std::string row = "0,1,2,3,1,0,0,0,0,0,1\n";
  const struct {
    const char* name;
    std::string bytes;
    const char* where;
    const char* reason;
  } cases[] = {
      {"empty.csv", "", "empty.csv", "not a device recording"},
      {"path.csv", "t,x,y,z,drill_on\n0,0,0,0,1\n", "path.csv:1", "not a device recording"},
      {"binary.csv", std::string("\x89PNG\r\n\x1a\n\0\0\0", 11), "binary.csv:1",
       "not a device recording"},
      {"header.csv", header, "header.csv", "no rows after the header"},
      {"fields.csv", header + "0,1,2,3\n", "fields.csv:2", "expected 11 fields"},
      {"text.csv", header + row + "0.001,1,two,3,1,0,0,0,0,0,1\n", "text.csv:3",
       "y 'two' is not a number"},
      {"time.csv", header + row + "0,1,2,3,1,0,0,0,0,0,1\n", "time.csv:3",
       "is not after the previous row"},
      {"nan_t.csv", header + "nan,1,2,3,1,0,0,0,0,0,1\n", "nan_t.csv:2", "t must be a finite time"},
      {"negative.csv", header + "-1,1,2,3,1,0,0,0,0,0,1\n", "negative.csv:2",
       "t must be a finite time"},
      {"hour.csv", header + row + "3600.5,1,2,3,1,0,0,0,0,0,1\n", "hour.csv:3", "at most 3600 s"},
      {"buttons.csv", header + "0,1,2,3,1,0,0,0,1.5,0,1\n", "buttons.csv:2",
       "buttons must be an integer"},
      {"pedal.csv", header + "0,1,2,3,1,0,0,0,0,2,1\n", "pedal.csv:2",
       "pedal must be a number in 0..1"},
      {"drill.csv", header + "0,1,2,3,1,0,0,0,0,0,2\n", "drill.csv:2", "drill_on must be 0 or 1"},
      {"long.csv", header + std::string(5000, '1') + "\n", "long.csv:2",
       "line longer than 1024 bytes"},
      {"old_row.csv", withSettings + row, "old_row.csv:2", "expected 13 fields"},
      {"rpm.csv", withSettings + "0,1,2,3,1,0,0,0,0,0,1,50,0\n", "rpm.csv:2",
       "rpm must be 0 (not recorded) or 100..100000"},
      {"irrigation.csv", withSettings + "0,1,2,3,1,0,0,0,0,0,1,1000,2\n", "irrigation.csv:2",
       "irrigation must be 0 or 1"},
  };
  for (const auto& c : cases) {
    test::writeBytes(path(c.name), c.bytes);
    try {
      loadRecording(path(c.name));
      ADD_FAILURE() << c.name << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path(c.where), 0), 0u) << what;
      EXPECT_NE(what.find(c.reason), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  EXPECT_THROW(loadRecording(path("missing.csv")), InputError);
  // A byte order mark, CRLF, spaces and blank lines are fine; nan in a pose is a device fault.
  test::writeBytes(path("ok.csv"), "\xEF\xBB\xBF" + std::string(kRecordingHeaderWithoutSettings) +
                                       "\r\n0, 1,2,3 ,1,0,0,0,0,0,1\r\n\r\n"
                                       "0.001,nan,2,3,1,0,0,0,0,0.5,0\n");
  const Recording ok = loadRecording(path("ok.csv"));
  ASSERT_EQ(ok.rows.size(), 2u);
  EXPECT_TRUE(std::isnan(ok.rows[1].positionMm.x));
  EXPECT_EQ(ok.rows[1].pedal, 0.5);
}

TEST_F(RecordingTest, TheReplayDeviceGivesTheNewestRowAtOrBeforeTheTimeAsked) {
  Recording r;
  for (int i = 0; i < 5; ++i) {
    RecordingRow row;
    row.tS = 1.0 + 0.002 * i;
    row.positionMm = glm::dvec3(i, 0, 0);
    r.rows.push_back(row);
  }
  ReplayDevice device("replay:x.csv", r);
  const Capabilities c = device.capabilities();
  EXPECT_TRUE(c.timeDriven && c.recorded && c.worldFrame && c.pose);
  EXPECT_EQ(c.startS, 1.0);
  EXPECT_EQ(c.endS, 1.008);
  DeviceSample s;
  device.poll(0.5, s);
  EXPECT_LT(s.tS, 0.0);  // before the recording: no sample
  device.poll(1.0, s);
  EXPECT_EQ(s.positionMm.x, 0.0);
  device.poll(1.003, s);
  EXPECT_EQ(s.positionMm.x, 1.0);
  EXPECT_EQ(s.tS, 1.002);
  device.poll(1.004, s);
  EXPECT_EQ(s.positionMm.x, 2.0);
  device.poll(9.0, s);
  EXPECT_EQ(s.positionMm.x, 4.0);
  device.poll(1.001, s);  // back in time (a restart)
  EXPECT_EQ(s.positionMm.x, 0.0);
}

}  // namespace
}  // namespace osteon::devices
