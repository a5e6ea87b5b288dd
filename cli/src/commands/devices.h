// `osteon devices list` and `osteon devices monitor DEVICE`: what is attached, and a device's
// events one per line.
#pragma once

#include <optional>
#include <string>

namespace osteon::cli {

struct DevicesListOptions {
  bool json = false;
};

struct DevicesMonitorOptions {
  std::string device;
  std::optional<long long> count;   // stop after this many events
  std::optional<double> durationS;  // stop after this long
  bool json = false;
};

struct DevicesCommandOptions {
  std::string which;  // "list" or "monitor": the one given
  DevicesListOptions list;
  DevicesMonitorOptions monitor;
};

int runDevicesList(const DevicesListOptions& options);
int runDevicesMonitor(const DevicesMonitorOptions& options);
int runDevices(const DevicesCommandOptions& options);  // the one given

}  // namespace osteon::cli
