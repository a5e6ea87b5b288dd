// `touch[:NAME]`: a Geomagic Touch (Phantom Omni) through OpenHaptics' HD API, built only
// with -DOSTEON_OPENHAPTICS=ON when the SDK is found at configure time. The servo loop
// (OpenHaptics' scheduler, 1 kHz) reads the pose and buttons and sends the force set by the
// haptic loop; if the haptic loop stops setting forces for more than three servo periods, the
// servo loop ramps the force out by itself (0.1 N per period), so a stalled program cannot
// leave a force on the hand.
//
// Without the SDK, openTouch throws an InputError saying so. The HD calls are checked in
// tests/devices/touch_test.cpp against a fake HD API (tests/devices/fake_openhaptics).
#pragma once

#include <memory>
#include <string>

#include "osteon/devices/device.h"

namespace osteon::devices {

struct TouchOptions {
  double maxForceN = 3.3;   // the Touch's peak force
  int staleServoTicks = 3;  // servo periods without a new force before it ramps out
  double rampOutNPerTick = 0.1;
  std::uint32_t drillButtonMask = 1;  // the stylus' first (dark grey) button drills
};

// True when osteon was built with OpenHaptics.
bool touchAvailable();

// Opens the Touch named `configName` (the OpenHaptics configuration name, empty for the
// default device). Throws InputError naming `deviceName` and the reason.
std::unique_ptr<Device> openTouch(const std::string& deviceName, const std::string& configName,
                                  const TouchOptions& options = {});

}  // namespace osteon::devices
