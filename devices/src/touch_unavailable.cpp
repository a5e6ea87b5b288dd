// The Touch when osteon is built without OpenHaptics (the default: the SDK is not free to
// redistribute and is absent here). In its own translation unit so a program that brings its
// own openTouch (the fake-HD test) links without a clash.
#include "osteon/core/error.h"
#include "osteon/devices/touch.h"

namespace osteon::devices {

bool touchAvailable() {
  return false;
}

std::unique_ptr<Device> openTouch(const std::string& deviceName, const std::string&,
                                  const TouchOptions&) {
  throw InputError(
      deviceName +
      ": osteon was built without OpenHaptics (configure with -DOSTEON_OPENHAPTICS=ON where the "
      "OpenHaptics SDK is installed)");
}

}  // namespace osteon::devices
