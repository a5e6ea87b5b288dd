// The drill's settings from a device's controls (device_input.h): the knob turns the rpm from
// the run's own, a pedal past half runs the motor from half to full speed, button 2 toggles
// irrigation on each press, and a recording's own columns win over all of them.
#include <gtest/gtest.h>

#include "osteon/simulation/device_input.h"

namespace osteon::simulation {
namespace {

// A board-like device whose state the test sets.
class ControlsDevice final : public devices::Device {
 public:
  ControlsDevice() : Device("controls") {}
  devices::Capabilities capabilities() const override {
    devices::Capabilities c;
    c.pose = c.buttons = c.pedal = c.knob = true;
    return c;
  }
  void poll(double nowS, devices::DeviceSample& sample) noexcept override {
    sample = state;
    sample.tS = nowS;
  }
  devices::DeviceSample state;
};

DrillSettings settingsAfter(DeviceInput& input, double tS, DrillSettings base) {
  ToolPose pose;
  bool on = false;
  input.sample(tS, pose, on);
  input.settings(base);
  return base;
}

TEST(DrillControls, KnobPedalAndIrrigationButton) {
  ControlsDevice device;
  DeviceInputOptions io;
  io.settings = {1200.0, false};
  DeviceInput input(device, io);
  const DrillSettings base{1200.0, false};
  EXPECT_DOUBLE_EQ(settingsAfter(input, 0.000, base).rpm, 1200.0);
  device.state.knob = 4;  // four counts up
  EXPECT_DOUBLE_EQ(settingsAfter(input, 0.001, base).rpm, 1200.0 + 4 * kRpmPerKnobCount);
  device.state.knob = -1000;  // never below the motor's floor
  EXPECT_DOUBLE_EQ(settingsAfter(input, 0.002, base).rpm, kMinRpm);
  device.state.knob = 0;
  device.state.pedal = 0.75;  // past half: three quarters speed
  EXPECT_DOUBLE_EQ(settingsAfter(input, 0.003, base).rpm, 900.0);
  device.state.pedal = 0.3;  // not drilling by the pedal: the set speed
  EXPECT_DOUBLE_EQ(settingsAfter(input, 0.004, base).rpm, 1200.0);
  // Button 2 toggles on its press, not while held; the base's irrigation is what it toggles.
  device.state.buttons = kIrrigationButtonMask;
  EXPECT_TRUE(settingsAfter(input, 0.005, base).irrigation);
  EXPECT_TRUE(settingsAfter(input, 0.006, base).irrigation);
  device.state.buttons = 0;
  EXPECT_TRUE(settingsAfter(input, 0.007, base).irrigation);
  device.state.buttons = kIrrigationButtonMask;
  EXPECT_FALSE(settingsAfter(input, 0.008, base).irrigation);
  // A recording's own settings pass through whatever the controls say.
  device.state.rpm = 1750.0;
  device.state.irrigation = true;
  const DrillSettings recorded = settingsAfter(input, 0.009, base);
  EXPECT_DOUBLE_EQ(recorded.rpm, 1750.0);
  EXPECT_TRUE(recorded.irrigation);
}

}  // namespace
}  // namespace osteon::simulation
