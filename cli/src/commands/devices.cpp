// `osteon devices list` and `osteon devices monitor DEVICE`: what is attached, and a device's
// events one per line (for a button board: every decoded line, malformed line with its
// reason, disconnect and reconnect).
#include "commands/devices.h"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "osteon/core/error.h"
#include "osteon/devices/button_board.h"
#include "osteon/devices/device.h"
#include "support/output.h"

namespace osteon::cli {

namespace dev = osteon::devices;
using nlohmann::json;

namespace {

std::string hex4(unsigned v) {
  std::ostringstream s;
  s << std::hex << std::setw(4) << std::setfill('0') << v;
  return s.str();
}

std::string seconds(double t) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << t;
  return s.str();
}

// One line out, now (a monitor is read as it runs, often through a pipe).
void emit(const std::string& line) {
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fputc('\n', stdout);
  std::fflush(stdout);
}

// Lines out a batch at a time: one write and one flush for every event waiting, so the
// monitor drains a fast board's queue (a flush per line could not keep up).
void emitBatch(std::string& batch) {
  if (batch.empty()) return;
  std::fwrite(batch.data(), 1, batch.size(), stdout);
  std::fflush(stdout);
  batch.clear();
}

// t as a number with millisecond precision.
double roundedMs(double t) {
  return double(std::llround(t * 1000.0)) / 1000.0;
}

std::string boardEventLine(const dev::BoardEvent& e, bool asJson) {
  using Kind = dev::BoardEvent::Kind;
  if (asJson) {
    json j = {{"t", roundedMs(e.tS)}};
    switch (e.kind) {
      case Kind::Line:
        j["buttons"] = e.buttons;
        j["pedal"] = e.pedal;
        j["knob"] = e.knob;
        break;
      case Kind::Malformed:
        j["error"] = e.reason;
        break;
      case Kind::Disconnected:
        j["status"] = "disconnected";
        break;
      case Kind::Connected:
        j["status"] = "connected";
        break;
    }
    return j.dump();
  }
  std::ostringstream s;
  s << seconds(e.tS) << " ";
  switch (e.kind) {
    case Kind::Line:
      s << "buttons=0x" << std::hex << e.buttons << std::dec << " pedal=" << e.pedal
        << " knob=" << e.knob;
      break;
    case Kind::Malformed:
      s << "error: " << e.reason;
      break;
    case Kind::Disconnected:
      s << "disconnected";
      break;
    case Kind::Connected:
      s << "connected";
      break;
  }
  return s.str();
}

std::string sampleLine(double t, const dev::DeviceSample& x, bool asJson) {
  if (asJson) {
    return json{
        {"t", roundedMs(t)},
        {"position_mm", {x.positionMm.x, x.positionMm.y, x.positionMm.z}},
        {"orientation", {x.orientation.w, x.orientation.x, x.orientation.y, x.orientation.z}},
        {"buttons", x.buttons},
        {"pedal", x.pedal},
        {"knob", x.knob},
        {"drill_on", x.drillOn},
        {"connected", x.connected}}
        .dump();
  }
  std::ostringstream s;
  s << seconds(t) << std::setprecision(6) << " position=(" << x.positionMm.x << ", "
    << x.positionMm.y << ", " << x.positionMm.z << ") orientation=(" << x.orientation.w << ", "
    << x.orientation.x << ", " << x.orientation.y << ", " << x.orientation.z << ") buttons=0x"
    << std::hex << x.buttons << std::dec << " pedal=" << x.pedal << " knob=" << x.knob
    << " drill=" << (x.drillOn ? "on" : "off") << (x.connected ? "" : " disconnected");
  return s.str();
}

bool sameState(const dev::DeviceSample& a, const dev::DeviceSample& b) {
  return a.positionMm == b.positionMm && a.orientation == b.orientation && a.buttons == b.buttons &&
         a.pedal == b.pedal && a.knob == b.knob && a.drillOn == b.drillOn &&
         a.connected == b.connected;
}

}  // namespace

namespace {

struct DevicesListReport {
  dev::DeviceList list;
};

json toJson(const DevicesListReport& r) {
  json devices = json::array();
  for (const dev::AttachedDevice& d : r.list.devices) {
    devices.push_back({{"name", d.name},
                       {"kind", d.kind},
                       {"path", d.path},
                       {"vendor_id", hex4(d.vendorId)},
                       {"product_id", hex4(d.productId)},
                       {"manufacturer", d.manufacturer},
                       {"product", d.product},
                       {"serial_number", d.serialNumber}});
  }
  return {{"devices", devices},
          {"serial_listing", r.list.serialListing},
          {"touch_built_in", r.list.touchBuiltIn}};
}

void printText(const DevicesListReport& r) {
  const dev::DeviceList& list = r.list;
  if (list.devices.empty()) {
    std::cout << "no devices attached (3Dconnexion HID devices"
              << (list.serialListing ? " and USB serial ports" : "") << " are listed)\n";
  }
  for (const dev::AttachedDevice& d : list.devices) {
    std::cout << d.name << "  " << hex4(d.vendorId) << ":" << hex4(d.productId) << "  "
              << d.manufacturer << (d.manufacturer.empty() ? "" : " ") << d.product << "\n";
  }
  if (list.touchBuiltIn)
    std::cout << "touch[:NAME]: the Geomagic Touch through OpenHaptics (built in)\n";
}

}  // namespace

int runDevicesList(const DevicesListOptions& options) {
  printReport(DevicesListReport{dev::listDevices()}, options.json);
  return kExitOk;
}

int runDevicesMonitor(const DevicesMonitorOptions& options) {
  if (options.count && *options.count < 1) {
    throw InputError("--count " + std::to_string(*options.count) + ": must be at least 1");
  }
  if (options.durationS && !(*options.durationS > 0.0 && *options.durationS <= 1e6)) {
    std::ostringstream s;
    s << "--duration " << *options.durationS << ": must be a positive number of seconds";
    throw InputError(s.str());
  }
  const dev::DeviceName name =
      dev::parseDeviceName(options.device.substr(0, options.device.find('+')));
  if (name.kind == "mouse" && options.device.find('+') == std::string::npos) {
    throw InputError(
        "mouse: the viewer's device (fed by its window); the command line has no mouse to monitor");
  }
  const std::unique_ptr<dev::Device> device = dev::openDevice(options.device);
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  long long events = 0;
  const auto done = [&] {
    return (options.count && events >= *options.count) ||
           (options.durationS && elapsed() >= *options.durationS);
  };

  // The last line of --json: how many events were shown and how many were lost.
  std::uint64_t dropped = 0;
  const auto ended = [&] {
    if (options.json) {
      emit(json{{"t", roundedMs(elapsed())},
                {"status", "ended"},
                {"events", events},
                {"events_dropped", dropped}}
               .dump());
    }
    if (dropped > 0) {
      std::fprintf(stderr,
                   "osteon: warning: %s: %llu events dropped: the monitor fell behind the device\n",
                   options.device.c_str(), static_cast<unsigned long long>(dropped));
    }
    return kExitOk;
  };

  if (auto* board = dynamic_cast<dev::ButtonBoardDevice*>(device.get())) {
    dev::BoardEvent e;
    std::string batch;
    bool warned = false;
    while (!done()) {
      bool any = false;
      while (batch.size() < (1u << 16) && !done() && board->nextEvent(e)) {
        batch += boardEventLine(e, options.json);
        batch += '\n';
        ++events;
        any = true;
      }
      // Events lost since the last batch (its queue was full): said where they were lost.
      const std::uint64_t lost = board->eventsDropped();
      if (lost > dropped) {
        dropped = lost;
        batch += options.json ? json{{"t", roundedMs(elapsed())},
                                     {"status", "dropped"},
                                     {"events_dropped", dropped}}
                                    .dump()
                              : seconds(elapsed()) + " dropped: " + std::to_string(dropped) +
                                    " events so far";
        batch += '\n';
        if (!warned) {  // once now, the total at the end
          std::fprintf(stderr,
                       "osteon: warning: %s: events dropped: the monitor fell behind the device\n",
                       options.device.c_str());
          warned = true;
        }
      }
      emitBatch(batch);
      if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return ended();
  }

  // Any other device: its state whenever it changes, polled at 100 Hz.
  const dev::Capabilities caps = device->capabilities();
  dev::DeviceSample sample, shown;
  bool any = false;
  while (!done()) {
    const double t = caps.timeDriven ? caps.startS + elapsed() : elapsed();
    if (caps.timeDriven && t > caps.endS + 0.01) break;  // the recording or path has ended
    device->poll(t, sample);
    if (sample.tS >= 0.0 && (!any || !sameState(sample, shown))) {
      emit(sampleLine(t, sample, options.json));
      shown = sample;
      any = true;
      ++events;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return ended();
}

int runDevices(const DevicesCommandOptions& options) {
  return options.which == "list" ? runDevicesList(options.list)
                                 : runDevicesMonitor(options.monitor);
}

}  // namespace osteon::cli
