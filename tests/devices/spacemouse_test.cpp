// The SpaceMouse: its report parser on byte sequences of each layout, the integrator's speed
// and dead zone, the device fed through a fake report source (no virtual HID device can be
// made here), and hidapi's real enumeration, which finds none and does not fail.
#include "osteon/devices/spacemouse.h"

#include <chrono>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "osteon/core/error.h"

namespace osteon::devices {
namespace {

using Bytes = std::vector<std::uint8_t>;

SpaceMouseReport parse(const Bytes& bytes, SpaceMouseAxes& axes) {
  return parseSpaceMouseReport(bytes.data(), bytes.size(), axes);
}

TEST(SpaceMouseReports, OlderDevicesSplitTranslationRotationAndButtons) {
  SpaceMouseAxes axes;
  // id 1: tx = 100, ty = -2, tz = 350 (little-endian int16)
  EXPECT_EQ(parse({0x01, 0x64, 0x00, 0xfe, 0xff, 0x5e, 0x01}, axes), SpaceMouseReport::Translation);
  EXPECT_EQ(axes.translation[0], 100);
  EXPECT_EQ(axes.translation[1], -2);
  EXPECT_EQ(axes.translation[2], 350);
  EXPECT_EQ(axes.rotation[0], 0);
  // id 2: rx = -350, ry = 1, rz = -1
  EXPECT_EQ(parse({0x02, 0xa2, 0xfe, 0x01, 0x00, 0xff, 0xff}, axes), SpaceMouseReport::Rotation);
  EXPECT_EQ(axes.rotation[0], -350);
  EXPECT_EQ(axes.rotation[1], 1);
  EXPECT_EQ(axes.rotation[2], -1);
  EXPECT_EQ(axes.translation[0], 100);  // a rotation report leaves translation alone
  // id 3: buttons 1 and 2 (mask 0x03), then none
  EXPECT_EQ(parse({0x03, 0x03, 0x00}, axes), SpaceMouseReport::Buttons);
  EXPECT_EQ(axes.buttons, 0x03u);
  EXPECT_EQ(parse({0x03, 0x00}, axes), SpaceMouseReport::Buttons);
  EXPECT_EQ(axes.buttons, 0u);
  // A SpacePilot's wider mask (4 bytes)
  EXPECT_EQ(parse({0x03, 0x01, 0x00, 0x10, 0x80}, axes), SpaceMouseReport::Buttons);
  EXPECT_EQ(axes.buttons, 0x80100001u);
}

TEST(SpaceMouseReports, NewerDevicesCombineTranslationAndRotation) {
  SpaceMouseAxes axes;
  // id 1, 13 bytes: tx ty tz rx ry rz = 1, 2, 3, -4, -5, 300
  const Bytes combined = {0x01, 0x01, 0x00, 0x02, 0x00, 0x03, 0x00,
                          0xfc, 0xff, 0xfb, 0xff, 0x2c, 0x01};
  EXPECT_EQ(parse(combined, axes), SpaceMouseReport::Combined);
  EXPECT_EQ(axes.translation, (std::array<std::int16_t, 3>{1, 2, 3}));
  EXPECT_EQ(axes.rotation, (std::array<std::int16_t, 3>{-4, -5, 300}));
  // Longer reports (padded to 64 bytes by some firmware) read the same.
  Bytes padded = combined;
  padded.resize(64, 0xAA);
  SpaceMouseAxes again;
  EXPECT_EQ(parse(padded, again), SpaceMouseReport::Combined);
  EXPECT_EQ(again.rotation, axes.rotation);
}

TEST(SpaceMouseReports, UnknownOrShortReportsChangeNothing) {
  SpaceMouseAxes axes;
  axes.translation = {7, 8, 9};
  axes.buttons = 5;
  const SpaceMouseAxes before = axes;
  for (const Bytes& bytes : std::vector<Bytes>{{},
                                               {0x01},
                                               {0x01, 0x00, 0x00},
                                               {0x02, 0x01, 0x02, 0x03},
                                               {0x04, 1, 2, 3, 4, 5, 6},
                                               {0x17, 0xff},
                                               {0x03}}) {
    EXPECT_EQ(parse(bytes, axes), SpaceMouseReport::Unknown) << bytes.size();
    EXPECT_EQ(axes.translation, before.translation);
    EXPECT_EQ(axes.buttons, before.buttons);
  }
  EXPECT_EQ(parseSpaceMouseReport(nullptr, 7, axes), SpaceMouseReport::Unknown);
}

TEST(SpaceMouseReports, KnownVendorsAndProducts) {
  EXPECT_TRUE(isSpaceMouse(0x256f, 0xc635));   // SpaceMouse Compact
  EXPECT_TRUE(isSpaceMouse(0x046d, 0xc626));   // SpaceNavigator
  EXPECT_FALSE(isSpaceMouse(0x046d, 0xc52b));  // a Logitech receiver, not a SpaceMouse
  EXPECT_FALSE(isSpaceMouse(0x2341, 0x0043));  // an Arduino
}

TEST(SpaceMouseIntegration, DeadZoneSpeedAndWorkspace) {
  SpaceMouseOptions options;
  options.fullScale = 350.0;
  options.deadZone = 0.1;  // 35 units of rest
  options.translationMmPerS = 50.0;
  options.rotationDegPerS = 90.0;
  options.workspaceMm = 20.0;
  SpaceMouseIntegrator integrator(options);
  EXPECT_EQ(integrator.shaped(30.0), 0.0);
  EXPECT_EQ(integrator.shaped(-35.0), 0.0);
  EXPECT_DOUBLE_EQ(integrator.shaped(350.0), 1.0);
  EXPECT_DOUBLE_EQ(integrator.shaped(-500.0), -1.0);
  EXPECT_NEAR(integrator.shaped(192.5), 0.5, 1e-12);

  SpaceMouseAxes axes;
  axes.translation = {20, 0, 0};  // inside the dead zone: nothing moves
  integrator.advance(axes, 1.0);
  EXPECT_EQ(integrator.positionMm(), glm::dvec3(0.0));
  // Full deflection right for 0.1 s: 5 mm along +x; the cap pushed down (HID +z) moves -z.
  axes.translation = {350, 0, 350};
  integrator.advance(axes, 0.1);
  EXPECT_NEAR(integrator.positionMm().x, 5.0, 1e-12);
  EXPECT_NEAR(integrator.positionMm().z, -5.0, 1e-12);
  // Held far too long: the pose stays in its workspace.
  integrator.advance(axes, 10.0);
  EXPECT_NEAR(integrator.positionMm().x, 20.0, 1e-12);
  EXPECT_NEAR(integrator.positionMm().z, -20.0, 1e-12);
  // Full twist about z for 1 s: 90 degrees (the HID's rz sign flipped to the pose frame).
  axes = SpaceMouseAxes{};
  axes.rotation = {0, 0, -350};
  integrator.advance(axes, 1.0);
  const glm::dvec3 x = integrator.orientation() * glm::dvec3(1.0, 0.0, 0.0);
  EXPECT_NEAR(x.x, 0.0, 1e-9);
  EXPECT_NEAR(x.y, 1.0, 1e-9);
}

// Reports as a test hands them over; a report of size -1 is the device unplugged.
class FakeSource final : public HidReportSource {
 public:
  void add(Bytes report) {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(report));
  }
  int read(std::uint8_t* buf, std::size_t size, int timeoutMs) noexcept override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (gone_) return -1;
      if (!queue_.empty()) {
        Bytes r = std::move(queue_.front());
        queue_.pop_front();
        if (r.empty()) {
          gone_ = true;
          return -1;
        }
        const std::size_t n = std::min(size, r.size());
        std::copy(r.begin(), r.begin() + std::ptrdiff_t(n), buf);
        return int(n);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(std::min(timeoutMs, 2)));
    return 0;
  }
  bool reopen() noexcept override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!comeBack_) return false;
    gone_ = false;
    return true;
  }
  void comeBack() {
    std::lock_guard<std::mutex> lock(mutex_);
    comeBack_ = true;
  }

 private:
  std::mutex mutex_;
  std::deque<Bytes> queue_;
  bool gone_ = false, comeBack_ = false;
};

template <class Pred>
bool waitFor(Pred pred, int timeoutMs = 5000) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (!pred()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

TEST(SpaceMouseDevice, IntegratesReportsIntoAPoseAtEachPoll) {
  auto source = std::make_unique<FakeSource>();
  FakeSource* fake = source.get();
  SpaceMouseOptions options;
  options.deadZone = 0.0;
  options.translationMmPerS = 100.0;
  SpaceMouseDevice device("spacemouse:fake", std::move(source), options);
  const Capabilities caps = device.capabilities();
  EXPECT_TRUE(caps.pose);
  EXPECT_FALSE(caps.force);

  DeviceSample s;
  device.poll(10.0, s);
  EXPECT_EQ(s.tS, 10.0);  // the pose holds between reports: fresh at every poll
  EXPECT_EQ(s.positionMm, glm::dvec3(0.0));
  // Full right (older split report), left button pressed.
  fake->add({0x01, 0x5e, 0x01, 0x00, 0x00, 0x00, 0x00});
  fake->add({0x03, 0x01});
  ASSERT_TRUE(waitFor([&] { return device.reports() >= 2; }));
  device.poll(10.010, s);
  EXPECT_NEAR(s.positionMm.x, 1.0, 1e-9);  // 100 mm/s for 10 ms
  EXPECT_TRUE(s.drillOn);
  EXPECT_EQ(s.buttons, 1u);
  // A long pause between polls integrates as maxStepS (no leap).
  device.poll(20.0, s);
  EXPECT_NEAR(s.positionMm.x, 1.0 + 100.0 * options.maxStepS, 1e-9);
  // Unplugged: at rest and disconnected; back: connected again.
  fake->add({});
  ASSERT_TRUE(waitFor([&] {
    device.poll(20.0, s);
    return !s.connected;
  }));
  const glm::dvec3 held = s.positionMm;
  device.poll(20.01, s);
  EXPECT_EQ(s.positionMm, held);
  fake->comeBack();
  ASSERT_TRUE(waitFor([&] {
    device.poll(20.02, s);
    return s.connected;
  }));
}

TEST(SpaceMouseHid, EnumerationFindsNoneHereAndDoesNotFail) {
  // hidapi's real enumeration (this machine has no HID devices at all).
  const std::vector<HidDeviceInfo> mice = listSpaceMice();
  for (const HidDeviceInfo& m : mice) EXPECT_TRUE(isSpaceMouse(m.vendorId, m.productId));
  if (!mice.empty()) GTEST_SKIP() << "a SpaceMouse is attached: " << mice.front().path;
  try {
    openHidSource("spacemouse", "");
    FAIL() << "opened a SpaceMouse that is not there";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no 3Dconnexion device attached"), std::string::npos)
        << e.what();
  }
  try {
    openHidSource("spacemouse:/dev/hidraw99", "/dev/hidraw99");
    FAIL() << "opened /dev/hidraw99";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("spacemouse:/dev/hidraw99: cannot open", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace osteon::devices
