// Device names and the factory: what each name opens, the one-line errors for names that
// cannot be opened, the viewer's mouse, a composite of a recording and a button board, and
// the list of attached devices (none here, and no failure).
#include "osteon/devices/device.h"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/devices/button_board.h"
#include "osteon/devices/devices.h"
#include "osteon/devices/mouse.h"
#include "osteon/devices/recording.h"
#include "osteon/devices/touch.h"
#include "support/files.h"
#include "support/serial_board.h"

namespace osteon::devices {
namespace {

TEST(DeviceNames, ParseKindArgumentAndBaud) {
  DeviceName n = parseDeviceName("serial:/dev/ttyACM0@115200");
  EXPECT_EQ(n.kind, "serial");
  EXPECT_EQ(n.argument, "/dev/ttyACM0");
  EXPECT_EQ(n.baud, 115200);
  n = parseDeviceName("serial:/dev/ttyUSB1");
  EXPECT_EQ(n.baud, 9600);
  n = parseDeviceName("spacemouse");
  EXPECT_EQ(n.kind, "spacemouse");
  EXPECT_TRUE(n.argument.empty());
  n = parseDeviceName("spacemouse:/dev/hidraw3");
  EXPECT_EQ(n.argument, "/dev/hidraw3");
  n = parseDeviceName("touch:Left Arm");
  EXPECT_EQ(n.argument, "Left Arm");
  n = parseDeviceName("replay:runs/a:b.csv");  // only the first ':' separates
  EXPECT_EQ(n.argument, "runs/a:b.csv");
  EXPECT_EQ(parseDeviceName("scripted:portal-7").argument, "portal-7");
  EXPECT_EQ(parseDeviceName("mouse").kind, "mouse");
}

TEST(DeviceNames, BadNamesSayWhatIsExpected) {
  const struct {
    const char* name;
    const char* reason;
  } cases[] = {{"", "empty device name"},
               {"joystick", "unknown device"},
               {"Serial:/dev/ttyS0", "unknown device"},
               {"serial", "no port"},
               {"serial:", "no port"},
               {"serial:@9600", "no port"},
               {"serial:/dev/ttyACM0@12345", "not a standard rate"},
               {"serial:/dev/ttyACM0@fast", "not a standard rate"},
               {"serial:/dev/ttyACM0@", "not a standard rate"},
               {"replay", "no recording"},
               {"scripted:", "no path"},
               {"mouse:left", "takes no argument"},
               {"spacemouse:", "empty path"},
               {"touch:", "empty name"}};
  for (const auto& c : cases) {
    try {
      parseDeviceName(c.name);
      ADD_FAILURE() << c.name << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(c.reason), std::string::npos) << c.name << ": " << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
  try {
    parseDeviceName("joystick");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("serial:PORT[@BAUD]"), std::string::npos) << e.what();
  }
}

class FactoryTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("factory");
  void TearDown() override { std::filesystem::remove_all(dir_); }
};

std::string openError(const std::string& name, const DeviceOpeners& extra = {}) {
  try {
    openDevice(name, extra);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(opened)";
}

TEST_F(FactoryTest, NamesThatCannotBeOpenedAreOneLineErrors) {
  EXPECT_EQ(
      openError("serial:" + dir_ + "/ttyNone").rfind("serial:" + dir_ + "/ttyNone: cannot open", 0),
      0u);
  EXPECT_EQ(openError("replay:" + dir_ + "/none.csv")
                .rfind(dir_ + "/none.csv: cannot open the recording", 0),
            0u);
  EXPECT_NE(openError("scripted:portal-5").find("front end"), std::string::npos);
  EXPECT_NE(openError("spacemouse").find("no 3Dconnexion device attached"), std::string::npos);
  if (!touchAvailable()) {
    EXPECT_NE(openError("touch").find("built without OpenHaptics"), std::string::npos);
    EXPECT_NE(openError("touch:Arm").find("touch:Arm:"), std::string::npos);
  }
  EXPECT_NE(openError("replay:a.csv+").find("empty device name around '+'"), std::string::npos);
  // A front end opens the kinds it owns.
  DeviceOpeners extra;
  extra["scripted"] = [](const DeviceName& n) -> std::unique_ptr<Device> {
    return std::make_unique<MouseDevice>(n.text);  // any device will do
  };
  EXPECT_EQ(openDevice("scripted:portal-5", extra)->name(), "scripted:portal-5");
}

TEST_F(FactoryTest, OpensRecordingsAndJoinsAPoseDeviceWithAButtonBoard) {
  test::writeBytes(dir_ + "/r.csv", std::string(kRecordingHeaderWithoutSettings) +
                                        "\n0,1,2,3,1,0,0,0,0,0,0\n0.001,1,2,3,1,0,0,0,0,0,0\n");
  std::unique_ptr<Device> replay = openDevice("replay:" + dir_ + "/r.csv");
  EXPECT_TRUE(replay->capabilities().recorded);
  EXPECT_EQ(replay->capabilities().endS, 0.001);

  test::FakeBoard board;
  ASSERT_TRUE(board.open());
  std::unique_ptr<Device> both =
      openDevice("replay:" + dir_ + "/r.csv+serial:" + board.slavePath + "@19200");
  const Capabilities c = both->capabilities();
  EXPECT_TRUE(c.pose && c.pedal && c.buttons && c.timeDriven);
  ASSERT_TRUE(board.write("B=4,P=1023\n"));
  DeviceSample s;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    both->poll(0.001, s);
  } while (s.pedal < 1.0 && std::chrono::steady_clock::now() < deadline);
  EXPECT_EQ(s.positionMm, glm::dvec3(1, 2, 3));  // the recording's pose
  EXPECT_EQ(s.tS, 0.001);                        // and its time
  EXPECT_EQ(s.buttons, 4u);                      // the board's buttons and pedal
  EXPECT_EQ(s.pedal, 1.0);
  EXPECT_TRUE(s.drillOn);  // the pedal pressed drills

  EXPECT_NE(openError("replay:" + dir_ + "/r.csv+replay:" + dir_ + "/r.csv").find("more than one"),
            std::string::npos);
}

TEST(MouseDevice, TheRenderLoopFeedsItAndTheHapticLoopPollsIt) {
  MouseDevice mouse("mouse", 0.2);
  EXPECT_TRUE(mouse.capabilities().pose);
  DeviceSample s;
  mouse.poll(1.0, s);
  EXPECT_LT(s.tS, 0.0);  // not fed yet: no pose
  std::thread render([&] {
    for (int i = 1; i <= 100; ++i)
      mouse.feed(glm::dvec3(i, 0, 0), glm::dquat(1, 0, 0, 0), 1u, true);
  });
  render.join();
  mouse.poll(2.0, s);
  EXPECT_EQ(s.tS, 2.0);
  EXPECT_EQ(s.positionMm.x, 100.0);
  EXPECT_TRUE(s.drillOn);
  EXPECT_TRUE(s.connected);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the window stopped feeding
  mouse.poll(3.0, s);
  EXPECT_FALSE(s.connected);
}

TEST(DeviceList, FindsNoneHereAndDoesNotFail) {
  const DeviceList list = listDevices();
  for (const AttachedDevice& d : list.devices) {
    EXPECT_TRUE(d.kind == "spacemouse" || d.kind == "serial") << d.name;
    EXPECT_EQ(d.name, d.kind + ":" + d.path);
  }
  EXPECT_EQ(list.touchBuiltIn, touchAvailable());
  EXPECT_EQ(kInterfaceVersion, 1);
}

}  // namespace
}  // namespace osteon::devices
