// osteon::devices: what will live here.
//   - a haptic device interface (pose in, force out) with a safety layer (force clamp, watchdog)
//   - scripted and replay devices for tests and demos
//   - hidapi HID devices and the serial control board of the instruments (buttons, encoders)
// It stands alone: GLM and hidapi, nothing else of osteon's.
#pragma once

namespace osteon::devices {

inline constexpr int kInterfaceVersion = 0;

}  // namespace osteon::devices
