#include "osteon/simulation/device_input.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"

namespace osteon::simulation {

// ---- scripted ----

ScriptedDevice::ScriptedDevice(const std::string& name, DrillPath path)
    : Device(name), path_(std::move(path)) {}

devices::Capabilities ScriptedDevice::capabilities() const {
  devices::Capabilities c;
  c.pose = true;
  c.buttons = true;
  c.timeDriven = true;
  c.worldFrame = true;
  c.startS = 0.0;
  c.endS = path_.durationS();
  return c;
}

void ScriptedDevice::poll(double nowS, devices::DeviceSample& sample) noexcept {
  ToolPose pose;
  bool drillOn = false;
  path_.sample(nowS, pose, drillOn);
  sample.tS = nowS;
  sample.positionMm = pose.tipMm;
  sample.orientation = pose.orientation;
  sample.buttons = drillOn ? 1u : 0u;
  sample.pedal = 0.0;
  sample.drillOn = drillOn;
  sample.connected = true;
}

std::unique_ptr<devices::Device> openSessionDevice(const std::string& name,
                                                   const Session& session) {
  devices::DeviceOpeners extra;
  extra["scripted"] = [&session](const devices::DeviceName& n) -> std::unique_ptr<devices::Device> {
    if (isPathCsv(n.argument))
      return std::make_unique<ScriptedDevice>(n.text, loadPathCsv(n.argument));
    Portal portal = Portal::FiveOClock;
    try {
      portal = parsePortal(n.argument);
    } catch (const InputError& e) {
      throw InputError(n.text + ": " + e.marked() +
                       " (expected scripted:portal-5, scripted:portal-7 or scripted:PATH.csv)");
    }
    return std::make_unique<ScriptedDevice>(n.text, session.portalPath(portal).path);
  };
  return devices::openDevice(name, extra);
}

DeviceFrame defaultDeviceFrame(const Session& session) {
  const geometry::VoxelGrid& grid = session.grid();
  const glm::dvec3 lo = grid.originMm();
  const glm::dvec3 hi = grid.worldFromGrid(glm::dvec3(grid.dims()));
  DeviceFrame frame;
  frame.originMm = glm::dvec3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), hi.z + 20.0);
  return frame;
}

// ---- the adapter ----

DeviceInput::DeviceInput(devices::Device& device, const DeviceInputOptions& options)
    : device_(&device), caps_(device.capabilities()), options_(options), base_(options.settings) {
  devices::SafetyOptions safety = options.safety;
  if (caps_.force && caps_.maxForceN > 0.0)
    safety.forceLimitN = std::min(safety.forceLimitN, caps_.maxForceN);
  safety_ = devices::SafetyLayer(safety);
}

void DeviceInput::sample(double tS, ToolPose& pose, bool& drillOn) noexcept {
  const double deviceStartS = options_.clockFromRunStart && caps_.timeDriven ? caps_.startS : 0.0;
  device_->poll(tS + deviceStartS, sample_);
  if (sample_.tS >= 0.0) sample_.tS = std::max(0.0, sample_.tS - deviceStartS);
  if (!caps_.worldFrame)
    sample_.positionMm = options_.frame.originMm + options_.frame.scale * sample_.positionMm;
  if (!options_.recordedLoop) {
    safety_.loopTick(tS);
  } else if (sample_.tS >= 0.0 && sample_.tS != loopS_) {
    loopS_ = sample_.tS;
    safety_.loopTick(sample_.tS);  // a new row: one period of the loop that recorded it
  }
  applyControls();
  if (options_.recorder && sample_.tS >= 0.0 && sample_.tS != recordedS_) {
    recordedS_ = sample_.tS;
    options_.recorder->record(sample_.tS, sample_);
  }
  const devices::PoseVerdict& v = safety_.acceptPose(tS, sample_);
  if (v.valid) {
    pose.tipMm = v.positionMm;
    pose.orientation = v.orientation;
    drillOn = v.drillOn;
  } else {
    pose = ToolPose{};
    pose.tipMm = options_.frame.originMm;  // parked above the bone until the device speaks
    drillOn = false;
  }
}

void DeviceInput::applyControls() noexcept {
  if (sample_.rpm > 0.0) {  // a recording's own settings, as its run used them
    controlled_ = {sample_.rpm, sample_.irrigation};
    return;
  }
  DrillSettings s = base_;
  if (caps_.knob) s.rpm += kRpmPerKnobCount * double(sample_.knob);
  if (caps_.pedal && sample_.pedal > 0.5) s.rpm *= sample_.pedal;  // 0.5 at half .. 1 at floor
  s.rpm = std::clamp(s.rpm, kMinRpm, kMaxRpm);
  const bool down = (sample_.buttons & kIrrigationButtonMask) != 0;
  if (down && !buttonWasDown_) irrigationToggled_ = !irrigationToggled_;
  buttonWasDown_ = down;
  s.irrigation = base_.irrigation != irrigationToggled_;
  controlled_ = s;
  sample_.rpm = s.rpm;
  sample_.irrigation = s.irrigation;
}

void DeviceInput::settings(DrillSettings& settings) noexcept {
  base_ = settings;
  settings = controlled_;
}

void DeviceInput::apply(double tS, const glm::dvec3& forceN) noexcept {
  const glm::dvec3 out = safety_.limitForce(tS, forceN);
  device_->setForce(tS, out);
  status_.sample = sample_;
  status_.verdict = safety_.verdict();
  status_.faults = safety_.stats().faults;
  status_.forceState = safety_.forceState();
  status_.forceN = std::sqrt(out.x * out.x + out.y * out.y + out.z * out.z);
  published_.write(status_);
}

DeviceStatus DeviceInput::status() noexcept {
  return published_.read();
}

// ---- device-driven deterministic runs ----

DeviceRunResult runDevice(Session& session, devices::Device& device,
                          const DeviceRunOptions& options) {
  using Clock = std::chrono::steady_clock;
  const devices::Capabilities caps = device.capabilities();
  if (!caps.pose)
    throw InputError(device.name() +
                     ": gives no pose (buttons only): it cannot drive the tool alone");
  if (!caps.timeDriven) {
    throw InputError(device.name() +
                     ": a live device runs in real time (the threaded runtime), not step by step");
  }
  DeviceInputOptions inputOptions = options.input;
  inputOptions.recordedLoop = caps.recorded;
  inputOptions.clockFromRunStart = false;  // t below is the device's own time
  DeviceInput input(device, inputOptions);

  DeviceRunResult result;
  result.startS = caps.startS;
  result.endS = caps.endS;
  // drill's clock exactly: t = start + i * step, as many steps as its runner takes.
  const auto steps = std::size_t(std::llround((caps.endS - caps.startS) / options.stepS)) + 1;
  ForceMetrics metrics;
  metrics.reserveForStep(options.stepS);
  Durations stepNs;
  stepNs.reserve(steps);
  std::uint64_t ran = 0;
  for (std::size_t i = 0; i < steps; ++i) {
    StepInput in;
    in.tS = caps.startS + double(i) * options.stepS;
    input.sample(in.tS, in.pose, in.drillOn);
    in.settings = session.options().settings;
    input.settings(in.settings);
    if (!input.hasPose()) {
      ++result.stepsBeforePose;
      continue;
    }
    const Clock::time_point start = Clock::now();
    const HapticStep h = session.hapticStep(in);  // through the session's coupling
    stepNs.add(std::chrono::nanoseconds(Clock::now() - start).count());
    result.run.summary.tally(h);
    const ForceLogRow row = logRowOf(in, h, session.simulation());
    metrics.add(row.tS, row.magnitudeN);
    if (options.onRow) options.onRow(row);
    if (options.afterStep) options.afterStep(i, {in.tS, h.proxy, in.drillOn, in.settings}, h.step);
    input.apply(in.tS, h.forceN);  // the safety layer, after the coupling
    ++ran;
    if (interrupted()) break;  // SIGINT/SIGTERM: the caller throws Interrupted
  }
  RunSummary& s = result.run.summary;
  s.jitterN = metrics.jitterN();
  s.maxStepChangeN = metrics.maxStepChangeN();
  s.maxForceN = metrics.maxForceN();
  s.removedVolumeMm3 = session.removedVolumeMm3();
  s.hapticStepUs = stepNs.percentiles(1e3);
  s.steps = ran;
  s.totals = session.totals();
  s.coupling = session.coupling() ? CouplingMode::Proxy : CouplingMode::Direct;
  result.safety = input.safety().stats();
  return result;
}

}  // namespace osteon::simulation
