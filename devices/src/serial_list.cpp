// Listing USB serial ports: libserialport knows each port's USB vendor and product ids, so an
// Arduino board is found by its ids. (Port I/O is serial_port.cpp's: libserialport 0.1.1 looks
// every port up under /sys/class/tty, where pseudo-terminals have no entry.)
#include "serial_list.h"

#ifdef OSTEON_HAVE_LIBSERIALPORT
#include <libserialport.h>
#endif

namespace osteon::devices {

#ifdef OSTEON_HAVE_LIBSERIALPORT

bool serialListingAvailable() {
  return true;
}

std::vector<AttachedDevice> listUsbSerialPorts() {
  std::vector<AttachedDevice> found;
  sp_port** ports = nullptr;
  if (sp_list_ports(&ports) != SP_OK || !ports) return found;
  const auto text = [](const char* s) { return s ? std::string(s) : std::string(); };
  for (sp_port** p = ports; *p; ++p) {
    if (sp_get_port_transport(*p) != SP_TRANSPORT_USB) continue;
    AttachedDevice d;
    d.kind = "serial";
    d.path = text(sp_get_port_name(*p));
    d.name = "serial:" + d.path;
    int vendor = 0, product = 0;
    if (sp_get_port_usb_vid_pid(*p, &vendor, &product) == SP_OK) {
      d.vendorId = std::uint16_t(vendor);
      d.productId = std::uint16_t(product);
    }
    d.manufacturer = text(sp_get_port_usb_manufacturer(*p));
    d.product = text(sp_get_port_usb_product(*p));
    if (d.product.empty()) d.product = text(sp_get_port_description(*p));
    d.serialNumber = text(sp_get_port_usb_serial(*p));
    found.push_back(d);
  }
  sp_free_port_list(ports);
  return found;
}

#else

bool serialListingAvailable() {
  return false;
}
std::vector<AttachedDevice> listUsbSerialPorts() {
  return {};
}

#endif

}  // namespace osteon::devices
