#include "commands/replay.h"

#include "osteon/core/interrupt.h"
#include "osteon/devices/recording.h"
#include "osteon/simulation/device_input.h"
#include "support/audio_out.h"
#include "support/device_run.h"
#include "support/run_summary.h"

namespace osteon::cli {

namespace dev = osteon::devices;
namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

int runReplay(const ReplayCommandOptions& options) {
  return runReplay(options, DrillExtension{});
}

int runReplay(const ReplayCommandOptions& options, const DrillExtension& extension,
              devices::Recording* read) {
  // Everything that can be refused is refused before the work.
  checkDeviceRunOptions(options.bone, options.levels);
  const sim::ToolKind kind = sim::parseToolKind(options.tool);
  const sim::CouplingMode coupling =
      checkFeel(options.feel, options.coupling, couplingFor(options.coupling, false));
  dev::Recording recording = read ? std::move(*read) : dev::loadRecording(options.log);
  RunFolder files(options.outDir);
  std::vector<std::string> inputs = options.bone.inputFiles();
  inputs.push_back(options.log);
  geo::refuseOverwritingInputs({files.forcesPath, files.summaryPath, files.surfacePath}, inputs);
  AudioOut audio(options.audioOut, inputs);

  const bool live = options.igtl.port.has_value();
  checkIgtlOptions(options.igtl, live);

  sim::Session session =
      openDeviceRunSession(options.bone, options.levels, kind, coupling, options.feel,
                           {extension.sessionOptions, extension.openBone});
  if (extension.opened) extension.opened(session);
  const std::size_t rows = recording.rows.size();
  dev::ReplayDevice device("replay:" + options.log, std::move(recording));
  sim::ForceLogWriter forces(files.forcesPath, coupling == sim::CouplingMode::Proxy,
                             calibrated(options.feel));
  audio.follow(forces);
  sim::DeviceRunOptions ro;
  ro.input.settings = session.options().settings;
  ro.onRow = [&forces, &extension](const sim::ForceLogRow& row) {
    forces.write(row);
    if (extension.onRow) extension.onRow(row);
  };
  ro.afterStep = extension.afterStep;
  sim::RunSummary run;
  dev::SafetyStats safety;
  json recordingJson = {{"file", options.log}, {"rows", rows}};
  json extra;
  if (live) {
    // At the recording's pace, so that Slicer watches it as it was drilled; its forces come from
    // the threaded runtime's clock, not byte for byte the deterministic replay's.
    const dev::Capabilities caps = device.capabilities();
    ThreadedDeviceRun r =
        runDeviceThreaded(session, device, ro.input, caps.endS - caps.startS, forces, options.igtl);
    run = r.run;
    safety = r.safety;
    extra["runtime"] = std::move(r.runtime);
    recordingJson["start_s"] = caps.startS;
    recordingJson["end_s"] = caps.endS;
  } else {
    const sim::DeviceRunResult r = sim::runDevice(session, device, ro);
    run = r.run.summary;
    safety = r.safety;
    recordingJson["start_s"] = r.startS;
    recordingJson["end_s"] = r.endS;
    recordingJson["steps_before_pose"] = r.stepsBeforePose;
  }
  extra["faults"] = faultsJson(safety.faults);
  extra["safety"] = safetyJson(safety, ro.input.safety.forceLimitN);
  extra["recording"] = std::move(recordingJson);
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place
  forces.commit();
  audio.commit();
  if (extension.done) extension.done(session);

  const DeviceRunSetup setup{options.bone.input,
                             sim::toolKindName(kind),
                             session.grid().voxelSizeMm(),
                             options.levels,
                             options.json,
                             live ? "replay-threaded" : "replay",
                             options.allowEmpty,
                             extension.printReport};
  return finishDeviceRun(setup, files, session, run, extra, "replayed " + options.log);
}

}  // namespace osteon::cli
