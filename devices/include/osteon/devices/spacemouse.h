// `spacemouse[:PATH]`: a 3Dconnexion SpaceMouse (or SpaceNavigator, SpacePilot, ...) over
// hidapi. The cap's deflection is a velocity: translation and rotation reports are integrated
// into a pose with a configurable speed and dead zone.
//
// HID reports (little-endian signed 16-bit axes, about +-350 at full deflection):
//   older devices, split:   id 1: tx ty tz (7 bytes)   id 2: rx ry rz (7 bytes)
//                           id 3: button mask (1..4 bytes after the id)
//   newer devices, combined: id 1: tx ty tz rx ry rz (13 bytes); buttons in id 3 as above
// Vendor ids 0x046d (Logitech-era 3Dconnexion, known product ids only) and 0x256f (3Dconnexion).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "osteon/core/handoff.h"
#include "osteon/devices/device.h"

namespace osteon::devices {

inline constexpr std::uint16_t kVendor3Dconnexion = 0x256f;
inline constexpr std::uint16_t kVendorLogitech = 0x046d;
// True for the vendor/product pairs of 3Dconnexion devices.
bool isSpaceMouse(std::uint16_t vendorId, std::uint16_t productId);

// The cap's state as the reports leave it.
struct SpaceMouseAxes {
  std::array<std::int16_t, 3> translation{};  // tx ty tz, device units
  std::array<std::int16_t, 3> rotation{};     // rx ry rz
  std::uint32_t buttons = 0;
};

enum class SpaceMouseReport { Translation, Rotation, Combined, Buttons, Unknown };

// Applies one HID report (its first byte the report id) to `axes`. Pure: bytes in, state out.
// Unknown ids and reports too short for their id leave `axes` unchanged and say Unknown.
SpaceMouseReport parseSpaceMouseReport(const std::uint8_t* data, std::size_t size,
                                       SpaceMouseAxes& axes);

struct SpaceMouseOptions {
  double fullScale = 350.0;         // device units at full deflection
  double deadZone = 0.08;           // fraction of full scale that counts as rest
  double translationMmPerS = 60.0;  // at full deflection
  double rotationDegPerS = 90.0;    // at full deflection
  double workspaceMm = 150.0;       // the pose stays within this of the start, per axis
  glm::dvec3 startMm{0.0};
  // Device axes to pose axes: HID x right, y towards the user, z down (pushing the cap). Pose
  // axes are the device frame of capabilities(): +x right, +y away from the user, +z up.
  std::array<double, 3> translationSign{1.0, -1.0, -1.0};
  std::array<double, 3> rotationSign{1.0, -1.0, -1.0};
  std::uint32_t drillButtonMask = 1;  // the left button drills
  double maxStepS = 0.05;             // a longer poll interval integrates as this (no leaps)
};

// Integrates the cap's deflection into a pose. Pure apart from its own state.
class SpaceMouseIntegrator {
 public:
  explicit SpaceMouseIntegrator(const SpaceMouseOptions& options = {});
  // Normalised deflection of one axis after the dead zone: 0 inside it, then linear to +-1.
  double shaped(double value) const;
  // Moves the pose by the deflection held for dtS seconds.
  void advance(const SpaceMouseAxes& axes, double dtS);
  const glm::dvec3& positionMm() const { return positionMm_; }
  const glm::dquat& orientation() const { return orientation_; }
  const SpaceMouseOptions& options() const { return options_; }

 private:
  SpaceMouseOptions options_;
  glm::dvec3 positionMm_;
  glm::dquat orientation_{1.0, 0.0, 0.0, 0.0};
};

// Where reports come from: hidapi for a real device, a fake in tests (no virtual HID device
// can be made on a machine without uhid).
class HidReportSource {
 public:
  virtual ~HidReportSource() = default;
  // One report into buf: its size, 0 on timeout, -1 when the device is gone.
  virtual int read(std::uint8_t* buf, std::size_t size, int timeoutMs) noexcept = 0;
  // Opens the device again after it went away; false while it is still gone.
  virtual bool reopen() noexcept = 0;
};

struct HidDeviceInfo {
  std::string path;
  std::uint16_t vendorId = 0, productId = 0;
  std::string manufacturer, product, serialNumber;
};

// Every attached 3Dconnexion device (hidapi). None is not an error.
std::vector<HidDeviceInfo> listSpaceMice();
// hidapi on `path`, or on the first SpaceMouse found when `path` is empty. Throws InputError
// naming the device (none attached, cannot open).
std::unique_ptr<HidReportSource> openHidSource(const std::string& deviceName,
                                               const std::string& path);

class SpaceMouseDevice final : public Device {
 public:
  // Starts a reader thread on `source`.
  SpaceMouseDevice(const std::string& name, std::unique_ptr<HidReportSource> source,
                   const SpaceMouseOptions& options = {});
  ~SpaceMouseDevice() override;
  Capabilities capabilities() const override;
  // Integrates the latest deflection since the previous poll; the pose is fresh at every poll.
  void poll(double nowS, DeviceSample& sample) noexcept override;
  std::uint64_t reports() const { return reports_.load(std::memory_order_relaxed); }

 private:
  struct State {
    SpaceMouseAxes axes;
    bool connected = true;
  };
  void readLoop();

  std::unique_ptr<HidReportSource> source_;
  core::TripleBuffer<State> state_;
  State polled_;
  SpaceMouseIntegrator integrator_;
  double lastPollS_ = 0.0;
  bool polledOnce_ = false;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> reports_{0};
  std::thread reader_;
};

}  // namespace osteon::devices
