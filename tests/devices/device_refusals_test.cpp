// What a device must refuse or report rather than crash or lose quietly: a SpaceMouse path that
// is no hidraw node (hidapi's hidraw backend crashed on /dev/null, a FIFO, a regular file), and
// a board whose events nobody drains (every event past the queue's capacity is counted).
#include <chrono>
#include <cstdint>
#include <string>
#include <sys/stat.h>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/devices/button_board.h"
#include "osteon/devices/device.h"
#include "osteon/devices/spacemouse.h"
#include "support/files.h"
#include "support/serial_board.h"

namespace osteon::devices {
namespace {

class DeviceRefusalsTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("refusals");
  void TearDown() override { std::filesystem::remove_all(dir_); }
};

std::string openError(const std::string& path) {
  try {
    openDevice("spacemouse:" + path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(opened)";
}

TEST_F(DeviceRefusalsTest, ASpaceMousePathThatIsNoHidrawDeviceIsRefusedWithWhatItIs) {
  const std::string fifo = dir_ + "/fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string file = dir_ + "/report.bin";
  test::writeBytes(file, std::string("\x01\x02\x03", 3));
  struct Case {
    std::string path, reason;
  };
  for (const Case& c :
       {Case{"/dev/null", "class mem, not hidraw"}, Case{fifo, "not a HID device (a FIFO)"},
        Case{file, "not a HID device (a regular file)"}, Case{dir_, "not a HID device (a folder)"},
        Case{dir_ + "/none", "No such file or directory"}}) {
    const std::string what = openError(c.path);
    EXPECT_EQ(what.rfind("spacemouse:" + c.path + ": cannot open " + c.path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(c.reason), std::string::npos) << what;
  }
  // A terminal is a character device too, of another class.
  if (std::filesystem::exists("/dev/ptmx")) {
    EXPECT_NE(openError("/dev/ptmx").find("class tty, not hidraw"), std::string::npos)
        << openError("/dev/ptmx");
  }
}

TEST_F(DeviceRefusalsTest, EventsPastAFullQueueAreCountedAsDropped) {
  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  ButtonBoardOptions options;
  options.silentS = 60.0;  // no disconnect event while the test looks
  ButtonBoardDevice device("serial:" + board.slavePath, board.slavePath, options);
  constexpr int kCapacity = int(kBoardEventCapacity);
  constexpr int kLines = kCapacity + 84;
  std::string lines;
  for (int i = 0; i < kLines; ++i) {
    lines += "B=" + std::to_string(i % 8) + ",P=" + std::to_string(i % (kBoardPedalMax + 1)) + "\n";
  }
  ASSERT_TRUE(board.write(lines));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (device.lines() < std::uint64_t(kLines) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_EQ(device.lines(), std::uint64_t(kLines));
  // Nobody drained: the queue holds the first kCapacity, the other 84 were counted as they were
  // lost.
  EXPECT_EQ(device.eventsDropped(), 84u);
  BoardEvent e;
  int kept = 0;
  while (device.nextEvent(e)) {
    EXPECT_EQ(e.pedal, kept % (kBoardPedalMax + 1));
    ++kept;
  }
  EXPECT_EQ(kept, kCapacity);
  // Drained, the queue takes events again and the count stands.
  ASSERT_TRUE(board.write("B=1,P=7\n"));
  const auto again = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!device.nextEvent(e) && std::chrono::steady_clock::now() < again) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  EXPECT_EQ(e.pedal, 7);
  EXPECT_EQ(device.eventsDropped(), 84u);
}

}  // namespace
}  // namespace osteon::devices
