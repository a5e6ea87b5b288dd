// USB serial ports through libserialport (when osteon was built with it).
#pragma once

#include <vector>

#include "osteon/devices/device.h"

namespace osteon::devices {

bool serialListingAvailable();
// Ports on USB with their vendor/product ids and names; none is not an error.
std::vector<AttachedDevice> listUsbSerialPorts();

}  // namespace osteon::devices
