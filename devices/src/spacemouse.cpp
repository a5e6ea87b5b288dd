#include "osteon/devices/spacemouse.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cwchar>
#include <hidapi.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "osteon/core/error.h"

namespace osteon::devices {

bool isSpaceMouse(std::uint16_t vendorId, std::uint16_t productId) {
  if (vendorId == kVendor3Dconnexion) return true;
  if (vendorId != kVendorLogitech) return false;
  // 3Dconnexion products sold under Logitech's vendor id (SpaceMouse Plus, CadMan, Classic,
  // SpaceBall 5000, SpaceTraveller, SpacePilot, SpaceNavigator, SpaceExplorer, SpaceNavigator
  // for Notebooks, SpacePilot Pro, SpaceMouse Pro, NuLOOQ).
  static constexpr std::uint16_t kProducts[] = {0xc603, 0xc605, 0xc606, 0xc621, 0xc623, 0xc625,
                                                0xc626, 0xc627, 0xc628, 0xc629, 0xc62b, 0xc640};
  return std::find(std::begin(kProducts), std::end(kProducts), productId) != std::end(kProducts);
}

namespace {

std::int16_t le16(const std::uint8_t* p) {
  return std::int16_t(std::uint16_t(p[0]) | std::uint16_t(p[1]) << 8);
}

}  // namespace

SpaceMouseReport parseSpaceMouseReport(const std::uint8_t* data, std::size_t size,
                                       SpaceMouseAxes& axes) {
  if (!data || size < 2) return SpaceMouseReport::Unknown;
  switch (data[0]) {
    case 1:
      if (size >= 13) {
        for (int i = 0; i < 3; ++i) axes.translation[std::size_t(i)] = le16(data + 1 + 2 * i);
        for (int i = 0; i < 3; ++i) axes.rotation[std::size_t(i)] = le16(data + 7 + 2 * i);
        return SpaceMouseReport::Combined;
      }
      if (size >= 7) {
        for (int i = 0; i < 3; ++i) axes.translation[std::size_t(i)] = le16(data + 1 + 2 * i);
        return SpaceMouseReport::Translation;
      }
      return SpaceMouseReport::Unknown;
    case 2:
      if (size >= 7) {
        for (int i = 0; i < 3; ++i) axes.rotation[std::size_t(i)] = le16(data + 1 + 2 * i);
        return SpaceMouseReport::Rotation;
      }
      return SpaceMouseReport::Unknown;
    case 3: {
      std::uint32_t mask = 0;
      const std::size_t bytes = std::min<std::size_t>(size - 1, 4);
      for (std::size_t i = 0; i < bytes; ++i) mask |= std::uint32_t(data[1 + i]) << (8 * i);
      axes.buttons = mask;
      return SpaceMouseReport::Buttons;
    }
    default:
      return SpaceMouseReport::Unknown;
  }
}

SpaceMouseIntegrator::SpaceMouseIntegrator(const SpaceMouseOptions& options)
    : options_(options), positionMm_(options.startMm) {}

double SpaceMouseIntegrator::shaped(double value) const {
  const double dead = options_.deadZone * options_.fullScale;
  const double magnitude = std::abs(value);
  if (!(magnitude > dead) || !(options_.fullScale > dead)) return 0.0;
  const double s = std::min(1.0, (magnitude - dead) / (options_.fullScale - dead));
  return value < 0.0 ? -s : s;
}

void SpaceMouseIntegrator::advance(const SpaceMouseAxes& axes, double dtS) {
  if (!(dtS > 0.0)) return;
  glm::dvec3 velocity(0.0), omega(0.0);
  for (int i = 0; i < 3; ++i) {
    velocity[i] = options_.translationSign[std::size_t(i)] *
                  shaped(axes.translation[std::size_t(i)]) * options_.translationMmPerS;
    omega[i] = options_.rotationSign[std::size_t(i)] * shaped(axes.rotation[std::size_t(i)]) *
               glm::radians(options_.rotationDegPerS);
  }
  positionMm_ += velocity * dtS;
  for (int i = 0; i < 3; ++i) {
    positionMm_[i] = std::clamp(positionMm_[i], options_.startMm[i] - options_.workspaceMm,
                                options_.startMm[i] + options_.workspaceMm);
  }
  const double rate = glm::length(omega);
  if (rate > 0.0)
    orientation_ = glm::normalize(glm::angleAxis(rate * dtS, omega / rate) * orientation_);
}

// ---- hidapi ----

namespace {

bool hidReady() {
  static const bool ready = hid_init() == 0;
  return ready;
}

std::string utf8(const wchar_t* text) {
  std::string out;
  if (!text) return out;
  for (; *text; ++text) {
    const auto c = std::uint32_t(*text);
    if (c < 0x80) {
      out.push_back(char(c));
    } else if (c < 0x800) {
      out.push_back(char(0xC0 | (c >> 6)));
      out.push_back(char(0x80 | (c & 0x3F)));
    } else if (c < 0x10000) {
      out.push_back(char(0xE0 | (c >> 12)));
      out.push_back(char(0x80 | ((c >> 6) & 0x3F)));
      out.push_back(char(0x80 | (c & 0x3F)));
    } else if (c < 0x110000) {
      out.push_back(char(0xF0 | (c >> 18)));
      out.push_back(char(0x80 | ((c >> 12) & 0x3F)));
      out.push_back(char(0x80 | ((c >> 6) & 0x3F)));
      out.push_back(char(0x80 | (c & 0x3F)));
    }
  }
  return out;
}

// What a file is, for a message saying why it is no HID device.
const char* fileKind(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISBLK(mode)) return "a block device";
  return "not a character device";
}

// The kernel's class of a character device (/sys/dev/char/MAJ:MIN/subsystem -> .../hidraw),
// or "" when sysfs does not say.
std::string charDeviceClass(dev_t device) {
  const std::string link = "/sys/dev/char/" + std::to_string(major(device)) + ":" +
                           std::to_string(minor(device)) + "/subsystem";
  char target[4096];
  const ssize_t n = ::readlink(link.c_str(), target, sizeof target - 1);
  if (n <= 0) return "";
  const std::string text(target, std::size_t(n));
  const std::size_t slash = text.rfind('/');
  return slash == std::string::npos ? text : text.substr(slash + 1);
}

// hidapi's hidraw backend crashes on a path that is not a hidraw node (/dev/null, a file, a
// FIFO): every open goes through this check first. Empty when `path` is a hidraw device,
// else why it is not.
std::string notHidrawReason(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::strerror(errno);
  if (!S_ISCHR(st.st_mode)) return std::string("not a HID device (") + fileKind(st.st_mode) + ")";
  const std::string cls = charDeviceClass(st.st_rdev);
  if (cls == "hidraw") return "";
  return "not a HID device (a character device of class " +
         (cls.empty() ? std::string("unknown") : cls) + ", not hidraw)";
}

struct HidClose {
  void operator()(hid_device* d) const { hid_close(d); }
};
using HidDevicePtr = std::unique_ptr<hid_device, HidClose>;

class HidapiSource final : public HidReportSource {
 public:
  HidapiSource(std::string path, HidDevicePtr device)
      : path_(std::move(path)), device_(std::move(device)) {}
  int read(std::uint8_t* buf, std::size_t size, int timeoutMs) noexcept override {
    if (!device_) return -1;
    const int n = hid_read_timeout(device_.get(), buf, size, timeoutMs);
    if (n < 0) device_.reset();
    return n;
  }
  bool reopen() noexcept override {
    try {
      if (!notHidrawReason(path_).empty()) return false;  // gone, or another file in its place
    } catch (...) {
      return false;
    }
    device_.reset(hid_open_path(path_.c_str()));
    return device_ != nullptr;
  }

 private:
  std::string path_;
  HidDevicePtr device_;
};

}  // namespace

std::vector<HidDeviceInfo> listSpaceMice() {
  std::vector<HidDeviceInfo> found;
  if (!hidReady()) return found;
  for (const std::uint16_t vendor : {kVendorLogitech, kVendor3Dconnexion}) {
    hid_device_info* list = hid_enumerate(vendor, 0);
    for (const hid_device_info* d = list; d; d = d->next) {
      if (!isSpaceMouse(d->vendor_id, d->product_id)) continue;
      HidDeviceInfo info;
      info.path = d->path ? d->path : "";
      info.vendorId = d->vendor_id;
      info.productId = d->product_id;
      info.manufacturer = utf8(d->manufacturer_string);
      info.product = utf8(d->product_string);
      info.serialNumber = utf8(d->serial_number);
      // A device with several interfaces appears once per interface: keep one per path.
      if (std::none_of(found.begin(), found.end(),
                       [&](const HidDeviceInfo& f) { return f.path == info.path; })) {
        found.push_back(info);
      }
    }
    hid_free_enumeration(list);
  }
  return found;
}

std::unique_ptr<HidReportSource> openHidSource(const std::string& deviceName,
                                               const std::string& path) {
  if (!hidReady()) throw InputError(deviceName + ": hidapi could not start");
  std::string chosen = path;
  if (chosen.empty()) {
    const std::vector<HidDeviceInfo> mice = listSpaceMice();
    if (mice.empty()) {
      throw InputError(
          deviceName +
          ": no 3Dconnexion device attached (vendor ids 046d, 256f); see osteon devices list");
    }
    chosen = mice.front().path;
  }
  const std::string notHid = notHidrawReason(chosen);
  if (!notHid.empty()) throw InputError(deviceName + ": cannot open " + chosen + ": " + notHid);
  HidDevicePtr device(hid_open_path(chosen.c_str()));
  if (!device) {
    const wchar_t* why = hid_error(nullptr);
    const std::string reason = why ? utf8(why) : std::string("cannot open");
    throw InputError(deviceName + ": cannot open " + chosen + " (" + reason + ")");
  }
  return std::make_unique<HidapiSource>(chosen, std::move(device));
}

// ---- the device ----

SpaceMouseDevice::SpaceMouseDevice(const std::string& name, std::unique_ptr<HidReportSource> source,
                                   const SpaceMouseOptions& options)
    : Device(name), source_(std::move(source)), integrator_(options) {
  reader_ = std::thread([this] { readLoop(); });
}

SpaceMouseDevice::~SpaceMouseDevice() {
  stop_.store(true);
  if (reader_.joinable()) reader_.join();
}

Capabilities SpaceMouseDevice::capabilities() const {
  Capabilities c;
  c.pose = true;
  c.buttons = true;
  return c;
}

void SpaceMouseDevice::readLoop() {
  State state;
  std::uint8_t report[64];
  while (!stop_.load(std::memory_order_relaxed)) {
    const int n = source_->read(report, sizeof report, 50);
    if (n > 0) {
      if (parseSpaceMouseReport(report, std::size_t(n), state.axes) != SpaceMouseReport::Unknown) {
        state.connected = true;
        state_.write(state);
        reports_.fetch_add(1, std::memory_order_relaxed);
      }
      continue;
    }
    if (n == 0) continue;
    // Gone: the cap is at rest until the device comes back (tried every half second).
    state = State{};
    state.connected = false;
    state_.write(state);
    while (!stop_.load(std::memory_order_relaxed) && !source_->reopen()) {
      for (int i = 0; i < 10 && !stop_.load(std::memory_order_relaxed); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    state.connected = true;
    state_.write(state);
  }
}

void SpaceMouseDevice::poll(double nowS, DeviceSample& sample) noexcept {
  polled_ = state_.read();
  const double dt =
      polledOnce_ ? std::clamp(nowS - lastPollS_, 0.0, integrator_.options().maxStepS) : 0.0;
  polledOnce_ = true;
  lastPollS_ = nowS;
  if (polled_.connected) integrator_.advance(polled_.axes, dt);
  sample.tS = nowS;
  sample.positionMm = integrator_.positionMm();
  sample.orientation = integrator_.orientation();
  sample.buttons = polled_.axes.buttons;
  sample.drillOn = (polled_.axes.buttons & integrator_.options().drillButtonMask) != 0;
  sample.pedal = 0.0;
  sample.connected = polled_.connected;
}

}  // namespace osteon::devices
