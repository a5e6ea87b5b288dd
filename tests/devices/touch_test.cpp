// The Geomagic Touch's use of OpenHaptics' HD API, checked against a fake HD API (the SDK and
// the arm are absent here): devices/src/touch_device.cpp is compiled into this test against
// tests/devices/fake_openhaptics/HD/hd.h, which records every call. What is checked: the calls
// to open, every servo frame, and close; the pose, buttons and force through them; the servo
// loop's own ramp-out when the haptic loop stops sending forces; errors as one line.
#include "osteon/devices/touch.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "fake_hd.h"
#include "osteon/core/error.h"

namespace osteon::devices {
namespace {

using Calls = std::vector<std::string>;

const Calls kServoFrame = {"hdBeginFrame(7)",
                           "hdGetDoublev(HD_CURRENT_TRANSFORM)",
                           "hdGetIntegerv(HD_CURRENT_BUTTONS)",
                           "hdSetDoublev(HD_CURRENT_FORCE)",
                           "hdEndFrame(7)",
                           "hdGetError"};

glm::dvec3 sentForce() {
  return glm::dvec3(fake_hd::arm().force[0], fake_hd::arm().force[1], fake_hd::arm().force[2]);
}

TEST(TouchHd, OpensServesAndClosesWithTheCallsOpenHapticsExpects) {
  fake_hd::reset();
  {
    std::unique_ptr<Device> touch = openTouch("touch", "");
    EXPECT_EQ(fake_hd::takeCalls(),
              (Calls{"hdInitDevice(default)", "hdGetError", "hdMakeCurrentDevice(7)",
                     "hdEnable(HD_FORCE_OUTPUT)", "hdScheduleAsynchronous(max)", "hdStartScheduler",
                     "hdGetError"}));
    const Capabilities c = touch->capabilities();
    EXPECT_TRUE(c.pose && c.buttons && c.force);
    EXPECT_EQ(c.maxForceN, 3.3);

    DeviceSample s;
    touch->poll(0.0, s);
    EXPECT_LT(s.tS, 0.0);  // no servo frame yet: no pose

    // The stylus at (10, 20, 30) mm, turned 90 degrees about z, its first button pressed.
    double* m = fake_hd::arm().transform;
    const double rotation[16] = {0, 1, 0, 0, -1, 0, 0, 0, 0, 0, 1, 0, 10, 20, 30, 1};
    std::copy(rotation, rotation + 16, m);
    fake_hd::arm().buttons = HD_DEVICE_BUTTON_1;
    EXPECT_EQ(fake_hd::runServo(1), 1);
    EXPECT_EQ(fake_hd::takeCalls(), kServoFrame);
    touch->poll(0.001, s);
    EXPECT_EQ(s.tS, 0.001);
    EXPECT_EQ(s.positionMm, glm::dvec3(10, 20, 30));
    const glm::dvec3 x = s.orientation * glm::dvec3(1, 0, 0);
    EXPECT_NEAR(x.y, 1.0, 1e-12);
    EXPECT_TRUE(s.drillOn);
    EXPECT_EQ(s.buttons, 1u);
    touch->poll(0.002, s);
    EXPECT_EQ(s.tS,
              0.001);  // no new servo frame: the sample keeps its time (a stall shows as a gap)

    // The force goes out at the next servo frame, clamped to the arm's limit.
    touch->setForce(0.002, glm::dvec3(0.0, 0.0, 1.5));
    fake_hd::runServo(1);
    EXPECT_EQ(sentForce(), glm::dvec3(0.0, 0.0, 1.5));
    touch->setForce(0.003, glm::dvec3(0.0, 4.0, 3.0));
    fake_hd::runServo(1);
    EXPECT_NEAR(glm::length(sentForce()), 3.3, 1e-12);
    fake_hd::takeCalls();

    // The haptic loop stops sending: three servo frames hold the force, then it ramps out at
    // 0.1 N per frame by the servo loop alone.
    fake_hd::runServo(3);
    EXPECT_NEAR(glm::length(sentForce()), 3.3, 1e-12);
    double previous = glm::length(sentForce());
    int frames = 0;
    while (glm::length(sentForce()) > 0.0 && frames < 100) {
      fake_hd::runServo(1);
      const double now = glm::length(sentForce());
      EXPECT_LE(previous - now, 0.1 + 1e-12);
      EXPECT_GE(previous - now, 0.0);
      previous = now;
      ++frames;
    }
    EXPECT_GE(frames, 33);  // 3.3 N in steps of (a hair under) 0.1 N
    EXPECT_LE(frames, 34);
    // A non-finite force is never sent.
    touch->setForce(0.1, glm::dvec3(std::nan(""), 0.0, 0.0));
    fake_hd::runServo(1);
    EXPECT_EQ(sentForce(), glm::dvec3(0.0));
    fake_hd::takeCalls();
  }
  EXPECT_EQ(fake_hd::takeCalls(),
            (Calls{"hdStopScheduler", "hdUnschedule(42)", "hdDisableDevice(7)"}));
}

TEST(TouchHd, AnArmThatDoesNotStartIsAnInputErrorNamingTheDevice) {
  fake_hd::reset();
  fake_hd::arm().failInit = HD_DEVICE_INITIALIZATION_FAILED;
  try {
    openTouch("touch:Left", "Left");
    FAIL() << "opened an arm that failed";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "touch:Left: cannot initialise the Touch (Device Initialization Failed)");
  }
  EXPECT_EQ(fake_hd::takeCalls(), (Calls{"hdInitDevice(Left)", "hdGetError"}));

  fake_hd::reset();
  fake_hd::arm().failStart = HD_COMM_ERROR;
  EXPECT_THROW(openTouch("touch", ""), InputError);
  const Calls calls = fake_hd::takeCalls();
  ASSERT_GE(calls.size(), 3u);  // everything it set up is taken down again
  EXPECT_EQ(Calls(calls.end() - 3, calls.end()),
            (Calls{"hdStopScheduler", "hdUnschedule(42)", "hdDisableDevice(7)"}));
}

}  // namespace
}  // namespace osteon::devices
