// Device names, the factory, the composite device and the list of what is attached.
#include "osteon/devices/device.h"

#include <algorithm>
#include <chrono>

#include "osteon/core/error.h"
#include "osteon/devices/button_board.h"
#include "osteon/devices/igtl_device.h"
#include "osteon/devices/mouse.h"
#include "osteon/devices/recording.h"
#include "osteon/devices/serial_port.h"
#include "osteon/devices/spacemouse.h"
#include "osteon/devices/touch.h"
#include "serial_list.h"

namespace osteon::devices {

double steadyNowS() noexcept {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

DeviceName parseDeviceName(const std::string& text) {
  DeviceName n;
  n.text = text;
  if (text.empty())
    throw InputError("--device '': empty device name (expected " + std::string(kDeviceNames) + ")");
  const std::size_t colon = text.find(':');
  n.kind = text.substr(0, colon);
  n.argument = colon == std::string::npos ? std::string() : text.substr(colon + 1);
  const bool hasColon = colon != std::string::npos;
  if (n.kind == "mouse") {
    if (hasColon) throw InputError(text + ": the mouse takes no argument (it is the viewer's own)");
  } else if (n.kind == "spacemouse" || n.kind == "touch") {
    if (hasColon && n.argument.empty())
      throw InputError(text + ": empty " + (n.kind == "touch" ? "name" : "path") + " after ':'");
  } else if (n.kind == "serial") {
    const std::size_t at = n.argument.rfind('@');
    if (at != std::string::npos) {
      const std::string baud = n.argument.substr(at + 1);
      n.argument.resize(at);
      const bool digits =
          !baud.empty() && baud.size() <= 8 &&
          std::all_of(baud.begin(), baud.end(), [](char c) { return c >= '0' && c <= '9'; });
      n.baud = digits ? std::stoi(baud) : 0;
      if (!digits || !SerialPort::supportedBaud(n.baud)) {
        throw InputError(text + ": baud rate '" + baud +
                         "' is not a standard rate (9600, 19200, 38400, 57600, 115200, ...)");
      }
    }
    if (n.argument.empty())
      throw InputError(text + ": no port (expected serial:PORT[@BAUD], e.g. serial:/dev/ttyACM0)");
  } else if (n.kind == "replay") {
    if (n.argument.empty()) throw InputError(text + ": no recording (expected replay:LOG.csv)");
  } else if (n.kind == "igtl") {
    if (n.argument.empty())
      throw InputError(text + ": no address (expected igtl:HOST:PORT[/NAME])");
  } else if (n.kind == "scripted") {
    if (n.argument.empty())
      throw InputError(text + ": no path (expected scripted:portal-5|portal-7|PATH.csv)");
  } else {
    throw InputError(text + ": unknown device (expected " + std::string(kDeviceNames) + ")");
  }
  return n;
}

namespace {

// `a+b`: one device made of several, as a trainer has them (a Touch for the drill, a board
// for the pedal). Pose, force and time from the first part with a pose; buttons and drill
// trigger from every part.
class CompositeDevice final : public Device {
 public:
  CompositeDevice(const std::string& name, std::vector<std::unique_ptr<Device>> parts)
      : Device(name), parts_(std::move(parts)), samples_(parts_.size()) {
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      const Capabilities c = parts_[i]->capabilities();
      if (c.pose && poseIndex_ == kNone) poseIndex_ = i;
      if (c.force && forceIndex_ == kNone) forceIndex_ = i;
    }
  }
  Capabilities capabilities() const override {
    Capabilities c;
    if (poseIndex_ != kNone) c = parts_[poseIndex_]->capabilities();
    c.force = false;
    c.maxForceN = 0.0;
    if (forceIndex_ != kNone) {
      c.force = true;
      c.maxForceN = parts_[forceIndex_]->capabilities().maxForceN;
    }
    for (const auto& p : parts_) {
      const Capabilities pc = p->capabilities();
      c.buttons = c.buttons || pc.buttons;
      c.pedal = c.pedal || pc.pedal;
      c.knob = c.knob || pc.knob;
    }
    return c;
  }
  void poll(double nowS, DeviceSample& sample) noexcept override {
    for (std::size_t i = 0; i < parts_.size(); ++i) parts_[i]->poll(nowS, samples_[i]);
    sample = poseIndex_ != kNone ? samples_[poseIndex_] : DeviceSample{};
    if (poseIndex_ == kNone) {
      sample.tS = -1.0;
      for (const DeviceSample& s : samples_) sample.tS = std::max(sample.tS, s.tS);
    }
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      if (i == poseIndex_) continue;
      const DeviceSample& s = samples_[i];
      sample.buttons |= s.buttons;
      sample.pedal = std::max(sample.pedal, s.pedal);
      sample.knob += s.knob;
      sample.drillOn = sample.drillOn || (s.drillOn && s.connected);
    }
  }
  void setForce(double nowS, const glm::dvec3& forceN) noexcept override {
    if (forceIndex_ != kNone) parts_[forceIndex_]->setForce(nowS, forceN);
  }

 private:
  static constexpr std::size_t kNone = ~std::size_t(0);
  std::vector<std::unique_ptr<Device>> parts_;
  std::vector<DeviceSample> samples_;
  std::size_t poseIndex_ = kNone, forceIndex_ = kNone;
};

std::unique_ptr<Device> openOne(const std::string& text, const DeviceOpeners& extra) {
  const DeviceName n = parseDeviceName(text);
  const auto opener = extra.find(n.kind);
  if (opener != extra.end() && opener->second) return opener->second(n);
  if (n.kind == "mouse") return std::make_unique<MouseDevice>(n.text);
  if (n.kind == "spacemouse")
    return std::make_unique<SpaceMouseDevice>(n.text, openHidSource(n.text, n.argument));
  if (n.kind == "serial") {
    ButtonBoardOptions options;
    options.baud = n.baud;
    return std::make_unique<ButtonBoardDevice>(n.text, n.argument, options);
  }
  if (n.kind == "touch") return openTouch(n.text, n.argument);
  if (n.kind == "igtl") return openIgtlDevice(n.text, n.argument);
  if (n.kind == "replay") return std::make_unique<ReplayDevice>(n.text, loadRecording(n.argument));
  throw InputError(
      n.text +
      ": scripted devices follow a session's drill paths: open them through a front end "
      "(osteon::simulation::openSessionDevice)");
}

}  // namespace

std::unique_ptr<Device> openDevice(const std::string& name, const DeviceOpeners& extra) {
  if (name.find('+') == std::string::npos) return openOne(name, extra);
  // Every name is checked before any device is opened.
  std::vector<std::string> names;
  std::size_t start = 0;
  while (true) {
    const std::size_t plus = name.find('+', start);
    names.push_back(
        name.substr(start, plus == std::string::npos ? std::string::npos : plus - start));
    if (names.back().empty()) throw InputError(name + ": empty device name around '+'");
    parseDeviceName(names.back());
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  std::vector<std::unique_ptr<Device>> parts;
  for (const std::string& part : names) parts.push_back(openOne(part, extra));
  int poses = 0;
  for (const auto& p : parts) poses += p->capabilities().pose ? 1 : 0;
  if (poses > 1)
    throw InputError(
        name +
        ": more than one of these devices gives a pose (join one pose device with button devices)");
  return std::make_unique<CompositeDevice>(name, std::move(parts));
}

DeviceList listDevices() {
  DeviceList list;
  for (const HidDeviceInfo& h : listSpaceMice()) {
    AttachedDevice d;
    d.name = "spacemouse:" + h.path;
    d.kind = "spacemouse";
    d.path = h.path;
    d.vendorId = h.vendorId;
    d.productId = h.productId;
    d.manufacturer = h.manufacturer;
    d.product = h.product;
    d.serialNumber = h.serialNumber;
    list.devices.push_back(d);
  }
  list.serialListing = serialListingAvailable();
  for (AttachedDevice& d : listUsbSerialPorts()) list.devices.push_back(std::move(d));
  list.touchBuiltIn = touchAvailable();
  return list;
}

// ---- mouse ----

MouseDevice::MouseDevice(const std::string& name, double staleAfterS)
    : Device(name), staleAfterS_(staleAfterS) {}

Capabilities MouseDevice::capabilities() const {
  Capabilities c;
  c.pose = true;
  c.buttons = true;
  return c;
}

void MouseDevice::feed(const glm::dvec3& positionMm, const glm::dquat& orientation,
                       std::uint32_t buttons, bool drillOn) noexcept {
  state_.write(MouseState{positionMm, orientation, buttons, drillOn, steadyNowS()});
}

void MouseDevice::poll(double nowS, DeviceSample& sample) noexcept {
  last_ = state_.read();
  if (last_.fedAtS < 0.0) {
    sample = DeviceSample{};
    return;
  }
  sample.tS = nowS;  // the pose holds between frames
  sample.positionMm = last_.positionMm;
  sample.orientation = last_.orientation;
  sample.buttons = last_.buttons;
  sample.drillOn = last_.drillOn;
  sample.connected = steadyNowS() - last_.fedAtS <= staleAfterS_;
}

}  // namespace osteon::devices
