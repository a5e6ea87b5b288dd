// `osteon drill MESH --device NAME`: a run driven by a device through the safety layer,
// deterministic for a device that follows its own clock (a recording, a scripted path), else in
// real time for --duration; optionally recorded (--record).
#include <algorithm>
#include <memory>
#include <optional>
#include <sstream>

#include "commands/drill.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/devices/recording.h"
#include "osteon/simulation/device_input.h"
#include "osteon/simulation/path.h"
#include "support/audio_out.h"
#include "support/device_run.h"
#include "support/run_summary.h"

namespace osteon::cli {

namespace dev = osteon::devices;
namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

// --duration, and every part of the device name, parsed before any work (exit 2 at once).
void checkDeviceOptions(const DrillCommandOptions& options) {
  if (options.durationS &&
      !(*options.durationS > 0.0 && *options.durationS <= sim::kMaxPathDurationS)) {
    std::ostringstream s;
    s << "--duration " << *options.durationS << ": must be a number of seconds in (0, "
      << sim::kMaxPathDurationS << "]";
    throw InputError(s.str());
  }
  for (std::size_t start = 0; start <= options.device.size();) {
    const std::size_t plus = options.device.find('+', start);
    const dev::DeviceName n = dev::parseDeviceName(
        options.device.substr(start, plus == std::string::npos ? std::string::npos : plus - start));
    if (n.kind == "mouse") {
      throw InputError(
          "mouse: the viewer's device (fed by its window); the command line has no mouse "
          "(use spacemouse, touch, replay:LOG.csv or scripted:...)");
    }
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
}

// No output may overwrite an input, and --record is neither an input nor another output.
void refuseOverwriting(const DrillCommandOptions& options, const RunFolder& files) {
  std::vector<std::string> inputs = deviceInputs(options.device);
  for (const std::string& file : options.bone.inputFiles()) inputs.push_back(file);
  std::vector<std::string> outputs = {files.forcesPath, files.summaryPath, files.surfacePath};
  if (!options.record.empty()) {
    for (const std::string& out : outputs) {
      if (sameLexicalPath(options.record, out)) {
        throw InputError("--record " + options.record + ": is also the run's " + out);
      }
    }
    for (const std::string& in : inputs) {
      if (!in.empty() && sameLexicalPath(options.record, in)) {
        throw InputError("--record " + options.record +
                         ": is an input of the run (it would be overwritten)");
      }
    }
    outputs.push_back(options.record);
  }
  geo::refuseOverwritingInputs(outputs, inputs);
}

// Whether the device can drive this run, and how: true for the deterministic mode.
bool deterministicFor(const DrillCommandOptions& options, const dev::Capabilities& caps) {
  if (!caps.pose) {
    throw InputError(options.device +
                     ": gives no pose (buttons and pedal only); join it to a pose device, e.g. "
                     "touch+" +
                     options.device);
  }
  const bool deterministic = caps.timeDriven && !options.threaded;
  if (deterministic && options.durationS) {
    throw InputError("--duration: " + options.device + " ends with its path or recording (" +
                     std::to_string(caps.endS - caps.startS) +
                     " s); --duration is for live devices");
  }
  if (!caps.timeDriven && !options.durationS) {
    throw InputError(options.device +
                     ": a live device needs --duration S (how long to run, in seconds)");
  }
  return deterministic;
}

struct DeviceOutcome {
  sim::RunSummary run;
  dev::SafetyStats safety;
  json extra;
};

// The device driven through the session, deterministic or threaded; rows streamed to `forces`.
DeviceOutcome drive(const DrillCommandOptions& options, sim::Session& session, dev::Device& device,
                    const sim::DeviceInputOptions& io, bool deterministic,
                    sim::ForceLogWriter& forces) {
  const auto logRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  DeviceOutcome out;
  if (deterministic) {
    sim::DeviceRunOptions ro;
    ro.input = io;
    ro.onRow = logRow;
    const sim::DeviceRunResult r = sim::runDevice(session, device, ro);
    out.run = r.run.summary;
    out.safety = r.safety;
    out.extra["device"] = {{"name", options.device},
                           {"start_s", r.startS},
                           {"end_s", r.endS},
                           {"steps_before_pose", r.stepsBeforePose}};
    return out;
  }
  const dev::Capabilities caps = device.capabilities();
  // A recording runs for its length, whatever its stamps (DeviceInput shifts its clock).
  const double durationS = options.durationS ? *options.durationS : caps.endS - caps.startS;
  ThreadedDeviceRun r = runDeviceThreaded(session, device, io, durationS, forces, options.igtl);
  out.run = r.run;
  out.safety = r.safety;
  out.extra["runtime"] = std::move(r.runtime);
  out.extra["device"] = {
      {"name", options.device},
      {"duration_s", durationS},
      {"frame_origin_mm", {io.frame.originMm.x, io.frame.originMm.y, io.frame.originMm.z}}};
  return out;
}

}  // namespace

int runDrillWithDevice(const DrillCommandOptions& options) {
  checkDeviceRunOptions(options.bone, options.levels);
  const sim::ToolKind kind = sim::parseToolKind(options.tool);
  const sim::CouplingMode coupling =
      checkFeel(options.feel, options.coupling, couplingFor(options.coupling, false));
  checkDeviceOptions(options);
  RunFolder files(options.outDir);
  refuseOverwriting(options, files);
  std::vector<std::string> inputs = deviceInputs(options.device);
  for (const std::string& file : options.bone.inputFiles()) inputs.push_back(file);
  AudioOut audio(options.audioOut, inputs);

  sim::Session session =
      openDeviceRunSession(options.bone, options.levels, kind, coupling, options.feel);
  std::unique_ptr<dev::Device> device = sim::openSessionDevice(options.device, session);
  const dev::Capabilities caps = device->capabilities();
  const bool deterministic = deterministicFor(options, caps);
  checkIgtlOptions(options.igtl, !deterministic);

  // Recorded into a temporary, put in place only when the run and the recording are complete:
  // an existing recording stays until then (and is kept when the run fails or is stopped).
  std::optional<geo::OutputFile> recordFile;
  std::optional<dev::StreamRecorder> recorder;
  dev::RecorderOptions recorderOptions;
  recorderOptions.waitWhenFull = deterministic;  // a live loop never waits for the disk
  if (!options.record.empty()) {
    recordFile.emplace(options.record);
    recorderOptions.name = options.record;
    recorder.emplace(recordFile->tempPath(), recorderOptions);
  }

  sim::ForceLogWriter forces(files.forcesPath, coupling == sim::CouplingMode::Proxy,
                             calibrated(options.feel));
  audio.follow(forces);
  sim::DeviceInputOptions io;
  io.frame = sim::defaultDeviceFrame(session);
  io.settings = session.options().settings;
  io.recorder = recorder ? &*recorder : nullptr;
  double limitN = io.safety.forceLimitN;
  if (caps.force && caps.maxForceN > 0.0) limitN = std::min(limitN, caps.maxForceN);
  DeviceOutcome outcome = drive(options, session, *device, io, deterministic, forces);
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place (its recording
                         // neither)
  forces.commit();
  audio.commit();
  if (recorder) {
    recorder->close();
    outcome.extra["recording_out"] = options.record;
    outcome.extra["device"]["recorded_rows"] = recorder->rows();
    outcome.extra["device"]["recording_dropped_rows"] = recorder->dropped();
  }
  outcome.extra["faults"] = faultsJson(outcome.safety.faults);
  outcome.extra["safety"] = safetyJson(outcome.safety, limitN);
  const DeviceRunSetup setup{options.bone.input,
                             sim::toolKindName(kind),
                             session.bone().grid().voxelSizeMm(),
                             options.levels,
                             options.json,
                             deterministic ? "device" : "device-threaded",
                             options.allowEmpty};
  return finishDeviceRun(setup, files, session, outcome.run, outcome.extra,
                         "drilled with " + options.device, recordFile ? &*recordFile : nullptr);
}

}  // namespace osteon::cli
