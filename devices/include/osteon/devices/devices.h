// osteon::devices: haptic and input hardware behind one interface (device.h), the safety layer
// between any device and the session (safety.h), recording and replay (recording.h), and the
// devices: the viewer's mouse (mouse.h), a 3Dconnexion SpaceMouse over hidapi (spacemouse.h),
// the serial button board (button_board.h, serial_port.h), the Geomagic Touch through
// OpenHaptics (touch.h). It stands alone: osteon::core and GLM (hidapi, libserialport and
// OpenHaptics privately), nothing of geometry or simulation. docs/devices.md has the names, the
// wire protocol and how to add a device.
#pragma once

#include "osteon/devices/device.h"
#include "osteon/devices/recording.h"
#include "osteon/devices/safety.h"

namespace osteon::devices {

inline constexpr int kInterfaceVersion = 1;

}  // namespace osteon::devices
