// USB serial ports through libserialport (when osteon was built with it).
#pragma once

#include "osteon/devices/device.h"

#include <vector>

namespace osteon::devices {

bool serialListingAvailable();
// Ports on USB with their vendor/product ids and names; none is not an error.
std::vector<AttachedDevice> listUsbSerialPorts();

}  // namespace osteon::devices
