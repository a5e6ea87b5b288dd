#include "commands/replay.h"

#include "osteon/core/interrupt.h"
#include "osteon/devices/recording.h"
#include "osteon/simulation/device_input.h"
#include "support/device_run.h"
#include "support/run_summary.h"

namespace osteon::cli {

namespace dev = osteon::devices;
namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

int runReplay(const ReplayCommandOptions& options) {
  // Everything that can be refused is refused before the work.
  checkDeviceRunOptions(options.bone, options.levels);
  const sim::ToolKind kind = sim::parseToolKind(options.tool);
  const sim::CouplingMode coupling = couplingFor(options.coupling, false);
  dev::Recording recording = dev::loadRecording(options.log);
  RunFolder files(options.outDir);
  std::vector<std::string> inputs = options.bone.inputFiles();
  inputs.push_back(options.log);
  geo::refuseOverwritingInputs({files.forcesPath, files.summaryPath, files.surfacePath}, inputs);

  sim::Session session = openDeviceRunSession(options.bone, options.levels, kind, coupling);
  const std::size_t rows = recording.rows.size();
  dev::ReplayDevice device("replay:" + options.log, std::move(recording));
  sim::ForceLogWriter forces(files.forcesPath, coupling == sim::CouplingMode::Proxy);
  sim::DeviceRunOptions ro;
  ro.onRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  const sim::DeviceRunResult r = sim::runDevice(session, device, ro);
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place
  forces.commit();

  const DeviceRunSetup setup{options.bone.input,
                             sim::toolKindName(kind),
                             *options.bone.voxelSizeMm,
                             options.levels,
                             options.json,
                             "replay",
                             options.allowEmpty};
  json extra = {{"faults", faultsJson(r.safety.faults)},
                {"safety", safetyJson(r.safety, ro.input.safety.forceLimitN)},
                {"recording",
                 {{"file", options.log},
                  {"rows", rows},
                  {"start_s", r.startS},
                  {"end_s", r.endS},
                  {"steps_before_pose", r.stepsBeforePose}}}};
  return finishDeviceRun(setup, files, session, r.run.summary, extra, "replayed " + options.log);
}

}  // namespace osteon::cli
