// Devices (osteon::devices, which knows nothing of sessions) joined to a drilling session:
// the scripted device (a drill path played as a device), device names opened for a session,
// the adapter that makes any device the runtime's PoseSource and ForceSink through the safety
// layer, and device-driven runs in the deterministic mode (recordings, paths). Its own target,
// osteon::simulation_devices, so osteon::simulation stays free of devices.
//
//   Session session = Session::open("default", 1.0, options);
//   auto device = openSessionDevice("spacemouse", session);          // or touch, mouse, ...
//   DeviceInputOptions io;
//   io.frame = defaultDeviceFrame(session, *device);
//   DeviceInput input(*device, io);                                 // PoseSource + ForceSink
//   LiveRuntime live(session, input, &input);  live.start();        // viewer: render loop
//   ... input.status() from the render thread ...
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "osteon/core/handoff.h"
#include "osteon/devices/device.h"
#include "osteon/devices/recording.h"
#include "osteon/devices/safety.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

// `scripted:portal-5|portal-7|PATH.csv`: a drill path as a device (time-driven, in the
// session's frame, ends with the path).
class ScriptedDevice final : public devices::Device {
 public:
  ScriptedDevice(const std::string& name, DrillPath path);
  devices::Capabilities capabilities() const override;
  void poll(double nowS, devices::DeviceSample& sample) noexcept override;
  const DrillPath& path() const { return path_; }

 private:
  DrillPath path_;
};

// Opens a device by name for `session`: `scripted:portal-5|portal-7` on the session's bone and
// tool, `scripted:PATH.csv` (drill's path CSV), and every name devices::openDevice opens.
// Throws InputError naming the device and the reason.
std::unique_ptr<devices::Device> openSessionDevice(const std::string& name, const Session& session);

// Where a live device's own frame lands in the session's: world = originMm + scale * device
// (axes kept, so forces go back unrotated). Devices in the session's frame already (paths,
// recordings) ignore it.
struct DeviceFrame {
  glm::dvec3 originMm{0.0};
  double scale = 1.0;
};
// 20 mm above the top of the bone's grid, centred over it: the device's origin, where the
// tool waits before it is moved down onto the bone.
DeviceFrame defaultDeviceFrame(const Session& session);

struct DeviceInputOptions {
  devices::SafetyOptions safety;  // forceLimitN: lowered to the device's own limit when it has one
  DeviceFrame frame;
  devices::StreamRecorder* recorder = nullptr;  // every new sample, in the session's frame
  // A deterministic replay: the watchdog takes its periods from the recording's rows (the
  // recorded loop's timing), not from the virtual clock.
  bool recordedLoop = false;
  // The threaded runtime's and the viewer's clock starts at 0 with the run: a time-driven
  // device (a recording stamped 30-32 s, or at Unix time) is polled at its own start plus that
  // time, and its samples come back on the run's clock. runDevice passes the device's own time.
  bool clockFromRunStart = true;
  // The drill's settings before the controls act (the session's: --rpm, --irrigation); the
  // runtime's later ones (the viewer's panel) arrive through settings().
  DrillSettings settings;
};

// How a device's controls set the drill (docs/devices.md): the knob turns the rpm by this much
// per count from the base; a pedal pressed past half (it drills) runs the motor from half speed
// there to full speed at the floor, as a surgical drill's variable-speed pedal; button 2 (mask
// 4) toggles irrigation.
inline constexpr double kRpmPerKnobCount = 50.0;
inline constexpr std::uint32_t kIrrigationButtonMask = 4u;

// What a render loop shows of the device (published every haptic period).
struct DeviceStatus {
  devices::DeviceSample sample;  // in the session's frame
  devices::PoseVerdict verdict;
  devices::FaultCounts faults;
  devices::ForceState forceState = devices::ForceState::Off;
  double forceN = 0.0;  // |F| sent to the device
};

// Any device as the runtime's pose source and force sink: samples through the safety layer
// into the session, the session's force through the safety layer back to the device. sample()
// and apply() run in the haptic loop (as runtime.h calls them): no heap, no lock, no throw.
class DeviceInput final : public PoseSource, public ForceSink {
 public:
  DeviceInput(devices::Device& device, const DeviceInputOptions& options = {});
  void sample(double tS, ToolPose& pose, bool& drillOn) noexcept override;
  void apply(double tS, const glm::dvec3& forceN) noexcept override;
  // The drill's settings of the last sample: a recording's own, or the controls' on the base.
  void settings(DrillSettings& settings) noexcept override;

  // True once the device has given an accepted pose (before it, sample() gives the parked
  // pose at the frame's origin with the drill off).
  bool hasPose() const { return safety_.verdict().valid; }
  // The haptic loop's, or anyone's once the loops have stopped.
  const devices::SafetyLayer& safety() const { return safety_; }
  devices::Device& device() { return *device_; }
  // Any thread: the latest status.
  DeviceStatus status() noexcept;

 private:
  devices::Device* device_;
  devices::Capabilities caps_;
  DeviceInputOptions options_;
  devices::SafetyLayer safety_;
  devices::DeviceSample sample_;
  double recordedS_ = -1.0;   // the newest sample recorded
  double loopS_ = -1.0;       // the newest recorded loop period (recordedLoop)
  DrillSettings base_;        // the runtime's, as of the last settings()
  DrillSettings controlled_;  // this sample's
  bool irrigationToggled_ = false, buttonWasDown_ = false;
  void applyControls() noexcept;
  DeviceStatus status_;
  core::TripleBuffer<DeviceStatus> published_;
};

struct DeviceRunOptions {
  double stepS = 0.001;
  DeviceInputOptions input;
  // Rows as they come (e.g. ForceLogWriter::write); must not throw.
  std::function<void(const ForceLogRow& row)> onRow;
  // After each step, as DeterministicOptions::afterStep: the input with the simulated tool's
  // pose (the proxy's under proxy coupling) and the device's trigger, and the step's output.
  std::function<void(std::size_t step, const StepInput& input, const StepOutput& output)> afterStep;
};

struct DeviceRunResult {
  RunResult run;  // the summary's metrics (log rows go to onRow only)
  devices::SafetyStats safety;
  std::uint64_t stepsBeforePose = 0;  // ticks skipped before the device's first accepted pose
  double startS = 0.0, endS = 0.0;
};

// A time-driven device (a scripted path, a recording) drives the session in the deterministic
// mode: 1 ms steps from its start to its end, each pose through the safety layer, each force
// through it to the device. A scripted path gives drill's force log byte for byte, and so does
// its recording replayed. Throws InputError for a live device or one without a pose. Stops
// early once SIGINT/SIGTERM is recorded (core/interrupt.h; the caller throws Interrupted).
DeviceRunResult runDevice(Session& session, devices::Device& device,
                          const DeviceRunOptions& options = {});

}  // namespace osteon::simulation
