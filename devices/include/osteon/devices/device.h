// One interface for every input device a trainer drives a session with: a haptic arm (the
// Geomagic Touch), a 3Dconnexion SpaceMouse, the viewer's mouse, a serial button board and
// pedal, a recording, a scripted path. A device gives timestamped samples (a pose in mm and a
// quaternion, buttons, optional analog inputs) and may take a force (N) back; its capability
// record says which.
//
// Clock: every time is in seconds on the caller's clock (the haptic loop's), which only grows.
// Live devices stamp a sample with the poll time at which its data first arrived, so a
// sample's age is measured by the caller's own polls; devices whose pose holds between
// updates (mouse, SpaceMouse) are fresh at every poll. Time-driven devices (a scripted path, a
// recording) give the sample at the time asked, so a run over them needs no wall clock.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace osteon::devices {

// What a device gives and takes.
struct Capabilities {
  bool pose = false;  // position (mm) and orientation
  bool buttons = false;
  bool pedal = false;      // analog 0..1
  bool knob = false;       // relative encoder counts
  bool force = false;      // takes a force back
  double maxForceN = 0.0;  // what it can exert (3.3 N for the Touch); 0 without force
  // The sample is a function of the time asked (a path, a recording): runs over it may use a
  // virtual clock (deterministic), and it ends at endS.
  bool timeDriven = false;
  // A recording: each new sample is one period of the haptic loop that recorded it, so a
  // replay sees the recorded loop's timing (the safety layer's watchdog).
  bool recorded = false;
  double startS = 0.0;  // time-driven: the first sample's time
  double endS = 0.0;    // time-driven: the last sample's time
  // Poses already in the session's frame (paths, recordings of such); live devices give
  // poses in their own workspace, which a front end maps onto the bone.
  bool worldFrame = false;
};

// One sample of a device's state.
struct DeviceSample {
  double tS = -1.0;                            // when it was taken (caller's clock); < 0: none yet
  glm::dvec3 positionMm{0.0};                  // the tool tip
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};  // tool frame -> device frame (w, x, y, z)
  std::uint32_t buttons = 0;                   // bit i: button i pressed
  double pedal = 0.0;                          // 0 released .. 1 fully pressed
  std::int64_t knob = 0;                       // encoder counts summed since the device opened
  bool drillOn = false;                        // the device's drill trigger (button, pedal)
  bool connected = true;                       // false while the device is silent or gone
  // The drill's speed and irrigation the run used with this sample (recordings carry them;
  // DeviceInput sets them from the controls): rpm 0 when not known.
  double rpm = 0.0;
  bool irrigation = false;
};

class Device {
 public:
  explicit Device(std::string name) : name_(std::move(name)) {}
  virtual ~Device() = default;
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // The name it was opened by (`serial:/dev/ttyACM0@9600`), for messages.
  const std::string& name() const { return name_; }
  virtual Capabilities capabilities() const = 0;
  // The newest state at nowS. Called by one thread at a time (the haptic loop, or a render
  // loop); never blocks, allocates or throws.
  virtual void poll(double nowS, DeviceSample& sample) noexcept = 0;
  // The force (N, device frame) to render until the next call; devices without force ignore
  // it. Same thread as poll(); never blocks, allocates or throws. Pass it through the safety
  // layer (safety.h) first.
  virtual void setForce(double nowS, const glm::dvec3& forceN) noexcept {
    (void)nowS;
    (void)forceN;
  }

 private:
  std::string name_;
};

// A device name split into its parts: `kind[:argument][@baud]`.
struct DeviceName {
  std::string text;      // as given
  std::string kind;      // mouse, spacemouse, serial, touch, replay, scripted
  std::string argument;  // after the first ':' (a path, a port, a portal); may be empty
  int baud = 9600;       // serial only
};

// The names osteon knows, for messages.
inline constexpr const char* kDeviceNames =
    "mouse, spacemouse[:PATH], serial:PORT[@BAUD], touch[:NAME], replay:LOG.csv or "
    "scripted:portal-5|portal-7|PATH.csv, igtl:HOST:PORT[/NAME], or two of them joined by '+'";

// Parses one name (not a '+' composite). Throws InputError naming the text and the reason.
DeviceName parseDeviceName(const std::string& text);

// Opens names the module does not open itself (`scripted:`, which needs a session's drill
// paths): a front end registers one per kind.
using DeviceOpener = std::function<std::unique_ptr<Device>(const DeviceName& name)>;
using DeviceOpeners = std::map<std::string, DeviceOpener>;

// Opens a device by name. `a+b` joins two devices (composite.h): the pose and force of the
// first that has them, buttons and drill trigger of both. Throws InputError naming the device
// and the reason (unknown name, no such port, nothing attached, not built in).
std::unique_ptr<Device> openDevice(const std::string& name, const DeviceOpeners& extra = {});

// What is attached: 3Dconnexion HID devices and USB serial ports.
struct AttachedDevice {
  std::string name;  // as openDevice takes it: spacemouse:/dev/hidraw0, serial:/dev/ttyACM0
  std::string kind;  // spacemouse, serial
  std::string path;
  std::uint16_t vendorId = 0;
  std::uint16_t productId = 0;
  std::string manufacturer;
  std::string product;
  std::string serialNumber;
};

struct DeviceList {
  std::vector<AttachedDevice> devices;
  bool serialListing = false;  // built with libserialport (USB serial ports are listed)
  bool touchBuiltIn = false;   // built with OpenHaptics (touch[:NAME] opens)
};

// Enumerates HID (hidapi) and USB serial (libserialport) devices. Finding none is not an error.
DeviceList listDevices();

// Seconds on a steady clock (any fixed origin): the clock live loops poll devices with.
double steadyNowS() noexcept;

}  // namespace osteon::devices
