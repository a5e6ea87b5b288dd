// The serial button board: the line protocol on bytes, then the device end to end through a
// pseudo-terminal (a USB serial port as far as the code can tell): good lines, garbage bytes,
// a 100 kB line, a board that falls silent, a board that is unplugged and plugged back in.
#include "osteon/devices/button_board.h"

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "support/files.h"
#include "support/serial_board.h"

namespace osteon::devices {
namespace {

using Kind = BoardEvent::Kind;

std::vector<BoardEvent> feedAll(BoardLineParser& parser, const std::string& bytes,
                                std::size_t chunk = 0) {
  std::vector<BoardEvent> events;
  const auto emit = [&](const BoardEvent& e) { events.push_back(e); };
  if (chunk == 0) chunk = bytes.size() == 0 ? 1 : bytes.size();
  for (std::size_t i = 0; i < bytes.size(); i += chunk) {
    parser.feed(bytes.data() + i, std::min(chunk, bytes.size() - i), 0.0, emit);
  }
  return events;
}

BoardEvent decode(const std::string& line) {
  BoardEvent e;
  EXPECT_TRUE(BoardLineParser::decodeLine(line.data(), line.size(), e)) << line;
  return e;
}

TEST(BoardProtocol, DecodesButtonsPedalAndKnob) {
  BoardEvent e = decode("B=5,P=512");
  EXPECT_EQ(e.kind, Kind::Line);
  EXPECT_EQ(e.buttons, 5u);
  EXPECT_EQ(e.pedal, 512);
  EXPECT_FALSE(e.hasKnob);
  e = decode("B=1f,P=0,K=-3");
  EXPECT_EQ(e.buttons, 0x1fu);
  EXPECT_EQ(e.knob, -3);
  EXPECT_TRUE(e.hasKnob);
  e = decode("P=1023,B=FFFFFFFF,K=+12\r");  // any order, upper-case hex, CR before the newline
  EXPECT_EQ(e.kind, Kind::Line);
  EXPECT_EQ(e.buttons, 0xffffffffu);
  EXPECT_EQ(e.pedal, 1023);
  EXPECT_EQ(e.knob, 12);
  e = decode("B=0,P=7,T=23.5,FW=v2");  // keys osteon does not know are ignored
  EXPECT_EQ(e.kind, Kind::Line);
  EXPECT_EQ(e.pedal, 7);
  BoardEvent blank;
  EXPECT_FALSE(BoardLineParser::decodeLine("\r", 1, blank));
  EXPECT_FALSE(BoardLineParser::decodeLine("", 0, blank));
}

TEST(BoardProtocol, MalformedLinesSayWhy) {
  const struct {
    const char* line;
    const char* reason;
  } cases[] = {{"B=5", "P (the pedal) is missing"},
               {"P=5", "B (the button mask) is missing"},
               {"B=zz,P=1", "B is not a hex button mask"},
               {"B=,P=1", "B is not a hex button mask"},
               {"B=123456789,P=1", "B is not a hex button mask"},
               {"B=1,P=1024", "P is not a pedal value 0-1023"},
               {"B=1,P=-1", "P is not a pedal value 0-1023"},
               {"B=1,P=5x", "P is not a pedal value 0-1023"},
               {"B=1,P=5,K=", "K is not a signed integer"},
               {"B=1,P=5,K=1.5", "K is not a signed integer"},
               {"B=1,P=5,K=12345678901", "K is not a signed integer"},
               {"B=1,B=2,P=5", "B given twice"},
               {"B=1,P=5,P=6", "P given twice"},
               {"hello", "a field without '='"},
               {"B=1,P=5,", "a field without '='"},
               {"=3,B=1,P=5", "a field without a key"},
               {"B=1,\x01P=5", "not printable ASCII"},
               {"B=1,P=5\xff", "not printable ASCII"}};
  for (const auto& c : cases) {
    const BoardEvent e = decode(c.line);
    EXPECT_EQ(e.kind, Kind::Malformed) << c.line;
    EXPECT_NE(std::string(e.reason).find(c.reason), std::string::npos)
        << c.line << ": " << e.reason;
  }
}

TEST(BoardProtocol, SplitsAStreamIntoLinesHoweverItArrives) {
  const std::string stream = "B=1,P=10\nB=2,P=20\r\n\nB=3,P=30,K=-1\ngarbage\nB=4,P=40\n";
  for (std::size_t chunk : {std::size_t(1), std::size_t(3), std::size_t(7), stream.size()}) {
    BoardLineParser parser;
    const std::vector<BoardEvent> events = feedAll(parser, stream, chunk);
    ASSERT_EQ(events.size(), 5u) << chunk;
    EXPECT_EQ(events[0].pedal, 10);
    EXPECT_EQ(events[1].pedal, 20);
    EXPECT_EQ(events[2].knob, -1);
    EXPECT_EQ(events[3].kind, Kind::Malformed);
    EXPECT_EQ(events[4].buttons, 4u);
    EXPECT_EQ(parser.lines(), 4u);
    EXPECT_EQ(parser.malformed(), 1u);
  }
  // A partial line waits for its newline.
  BoardLineParser parser;
  EXPECT_TRUE(feedAll(parser, "B=1,P=").empty());
  EXPECT_EQ(feedAll(parser, "9\n").at(0).pedal, 9);
}

TEST(BoardProtocol, ALineOf100kBIsDroppedWithoutGrowingAndCountedMalformed) {
  BoardLineParser parser;
  const std::string huge(100 * 1024, 'A');
  std::vector<BoardEvent> events = feedAll(parser, "B=1,P=1\n" + huge, 4096);
  ASSERT_EQ(events.size(), 1u);  // the long line has no newline yet
  events = feedAll(parser, huge + "\nB=2,P=2\n", 4096);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::Malformed);
  EXPECT_STREQ(events[0].reason, "line longer than 256 bytes");
  EXPECT_EQ(events[1].kind, Kind::Line);
  EXPECT_EQ(events[1].pedal, 2);
  EXPECT_EQ(parser.malformed(), 1u);
  // The parser holds a fixed buffer, whatever it was fed.
  EXPECT_LE(sizeof(BoardLineParser), kMaxBoardLineBytes + 64);
  // Exactly at the bound is still a line.
  std::string longest = "B=1,P=1,X=";
  longest.resize(kMaxBoardLineBytes, 'x');
  events = feedAll(parser, longest + "\n" + longest + "y\n");
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::Line);
  EXPECT_EQ(events[1].kind, Kind::Malformed);
}

// Events from the device until `count` have come or the time is up.
std::vector<BoardEvent> waitEvents(ButtonBoardDevice& device, std::size_t count,
                                   int timeoutMs = 5000) {
  std::vector<BoardEvent> events;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  BoardEvent e;
  while (events.size() < count && std::chrono::steady_clock::now() < deadline) {
    if (device.nextEvent(e)) {
      events.push_back(e);
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  return events;
}

class BoardDeviceTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("board");
  void TearDown() override { std::filesystem::remove_all(dir_); }
};

TEST_F(BoardDeviceTest, DecodesABoardOnAPseudoTerminalEndToEnd) {
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  ButtonBoardDevice device("serial:" + board.slavePath, board.slavePath);
  EXPECT_FALSE(device.capabilities().pose);
  EXPECT_TRUE(device.capabilities().pedal);

  ASSERT_TRUE(board.write("B=5,P=512\n"));
  ASSERT_TRUE(board.write(std::string("\x00\x13\xfe\xffgarbage", 11) + "\n"));
  ASSERT_TRUE(board.write("B=zz,P=1\n"));
  ASSERT_TRUE(
      board.write(std::string(100 * 1024, 'A') + "\n"));  // the reader drains it as it comes
  ASSERT_TRUE(board.write("B=1f,P=1023,K=-3,X=9\r\n"));
  const std::vector<BoardEvent> events = waitEvents(device, 5);
  ASSERT_EQ(events.size(), 5u);
  EXPECT_EQ(events[0].kind, Kind::Line);
  EXPECT_EQ(events[0].buttons, 5u);
  EXPECT_EQ(events[0].pedal, 512);
  EXPECT_EQ(events[1].kind, Kind::Malformed);
  EXPECT_NE(std::string(events[1].reason).find("printable ASCII"), std::string::npos);
  EXPECT_EQ(events[2].kind, Kind::Malformed);
  EXPECT_EQ(events[3].kind, Kind::Malformed);
  EXPECT_STREQ(events[3].reason, "line longer than 256 bytes");
  EXPECT_EQ(events[4].kind, Kind::Line);
  EXPECT_EQ(events[4].knob, -3);
  EXPECT_EQ(device.lines(), 2u);
  EXPECT_EQ(device.malformed(), 3u);

  DeviceSample s;
  device.poll(1.0, s);
  EXPECT_EQ(s.tS, 1.0);  // new lines since the last poll: stamped now
  EXPECT_EQ(s.buttons, 0x1fu);
  EXPECT_DOUBLE_EQ(s.pedal, 1.0);
  EXPECT_EQ(s.knob, -3);
  EXPECT_TRUE(s.drillOn);
  EXPECT_TRUE(s.connected);
  device.poll(2.0, s);
  EXPECT_EQ(s.tS, 1.0);  // nothing new: the sample keeps its time
}

TEST_F(BoardDeviceTest, ABoardSilentForHalfASecondIsDisconnectedUntilItSpeaksAgain) {
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  ButtonBoardDevice device("serial:" + board.slavePath, board.slavePath);
  ASSERT_TRUE(board.write("B=1,P=100\n"));
  std::vector<BoardEvent> events = waitEvents(device, 2, 3000);  // the line, then silence
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::Line);
  EXPECT_EQ(events[1].kind, Kind::Disconnected);
  EXPECT_GE(events[1].tS - events[0].tS, 0.5);
  EXPECT_LT(events[1].tS - events[0].tS, 1.0);
  EXPECT_FALSE(device.connected());
  DeviceSample s;
  device.poll(5.0, s);
  EXPECT_FALSE(s.connected);
  ASSERT_TRUE(board.write("B=0,P=0\n"));
  events = waitEvents(device, 2);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::Connected);
  EXPECT_EQ(events[1].kind, Kind::Line);
  device.poll(6.0, s);
  EXPECT_TRUE(s.connected);
  EXPECT_FALSE(s.drillOn);
}

TEST_F(BoardDeviceTest, ABoardUnpluggedAndPluggedBackIsFoundAgainByItsName) {
  // The port by a stable name (as udev's /dev/serial/by-id links are), pointing at the pty.
  const std::string link = dir_ + "/board";
  auto board = std::make_unique<test::FakeBoard>();
  ASSERT_TRUE(board->open());
  test::pointLink(link, board->slavePath);
  ButtonBoardDevice device("serial:" + link, link);
  ASSERT_TRUE(board->write("B=3,P=300\n"));
  std::vector<BoardEvent> events = waitEvents(device, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].pedal, 300);

  board->unplug();  // hung up: disconnected at once, not after the silence
  const auto unpluggedAt = std::chrono::steady_clock::now();
  events = waitEvents(device, 1);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, Kind::Disconnected);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - unpluggedAt).count(),
            0.45);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // gone a while: tried and failed

  auto again = std::make_unique<test::FakeBoard>();
  ASSERT_TRUE(again->open());
  test::pointLink(link, again->slavePath);
  ASSERT_TRUE(again->write("B=2,P=1023\n"));
  events = waitEvents(device, 2);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::Connected);
  EXPECT_EQ(events[1].kind, Kind::Line);
  EXPECT_EQ(events[1].buttons, 2u);
  EXPECT_EQ(events[1].pedal, 1023);
}

TEST_F(BoardDeviceTest, APortThatIsNotThereIsAnInputErrorNamingTheDevice) {
  try {
    ButtonBoardDevice device("serial:" + dir_ + "/nothing", dir_ + "/nothing");
    FAIL() << "opened a port that is not there";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("serial:" + dir_ + "/nothing: cannot open the serial port", 0), 0u)
        << what;
    EXPECT_NE(what.find("No such file"), std::string::npos) << what;
  }
  // A file that is not a terminal.
  test::writeBytes(dir_ + "/plain", "B=1,P=1\n");
  EXPECT_THROW(ButtonBoardDevice("serial:" + dir_ + "/plain", dir_ + "/plain"), InputError);
  ButtonBoardOptions odd;
  odd.baud = 12345;
  EXPECT_THROW(ButtonBoardDevice("serial:x", "/dev/null", odd), InputError);
}

}  // namespace
}  // namespace osteon::devices
