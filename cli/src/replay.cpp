// `osteon replay LOG.csv MESH` and `osteon drill MESH --device NAME`: runs driven by a device
// through the safety layer (osteon::simulation_devices), written as `drill` writes its runs
// (forces.csv, summary.json, surface.ply) plus the device's faults and the safety layer's work.
#include "commands.h"
#include "run_summary.h"

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/devices/recording.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/device_input.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/session.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

namespace osteon::cli {

namespace dev = osteon::devices;
namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

struct RunSetup {
  std::string mesh;
  std::string tool;
  double voxelSizeMm = 0.0;
  int levels = 2;
  std::string outDir;
  bool json = false;
  std::string mode;           // replay, device, device-threaded
  bool allowEmpty = false;
};

void checkRunOptions(const BoneSource& bone, int levels) {
  sim::DrillingOptions drilling;
  drilling.levels = levels;
  sim::validateDrillingOptions(drilling);
  bone.check();
}

// The session a device run drills: the bone opened from its source, then drilled.
sim::Session openSession(const BoneSource& bone, int levels, sim::ToolKind kind, sim::CouplingMode coupling) {
  BoneSource source = bone;
  source.sampleFineFills = levels > 0;
  sim::SessionOptions so;
  so.coupling = coupling;
  so.levels = levels;
  so.tool = kind;
  so.keepSurface = false;  // batch runs: the surface is extracted once at the end
  return sim::Session(sim::BoneModel::open(source).bone, so);
}

// The run's files are one set, put in place together at the end (output_dir.h).
geo::OutputDir openOutDir(const std::string& dir) {
  return geo::OutputDir(dir, {"forces.csv", "summary.json", "surface.ply"});
}

// The files a device name reads (recordings, path CSVs), which no output may overwrite.
std::vector<std::string> deviceInputs(const std::string& name) {
  std::vector<std::string> files;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t plus = name.find('+', start);
    const std::string part = name.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
    const std::size_t colon = part.find(':');
    if (colon != std::string::npos) {
      const std::string kind = part.substr(0, colon), argument = part.substr(colon + 1);
      if (kind == "replay" || (kind == "scripted" && sim::isPathCsv(argument))) files.push_back(argument);
    }
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  return files;
}

bool sameLexicalPath(const std::string& a, const std::string& b) {
  std::error_code ec;
  const auto na = std::filesystem::weakly_canonical(std::filesystem::absolute(a, ec), ec);
  const auto nb = std::filesystem::weakly_canonical(std::filesystem::absolute(b, ec), ec);
  return na == nb;
}

json faultsJson(const dev::FaultCounts& f) {
  return {{"nan", f.nonFinite}, {"gaps", f.gaps}, {"jumps", f.jumps}, {"watchdog", f.watchdog}};
}

json safetyJson(const dev::SafetyStats& s, double limitN) {
  return {{"clamped_steps", s.clampedSteps},       {"ramp_steps", s.rampSteps},
          {"held_steps", s.heldSteps},             {"fault_steps", s.faultSteps},
          {"non_finite_forces", s.nonFiniteForces}, {"engagements", s.engagements},
          {"max_force_n", s.maxForceN},             {"max_step_change_n", s.maxStepChangeN},
          {"force_limit_n", limitN}};
}

// Writes summary.json and the surface, puts the run's files (and a recording) in place, prints
// the summary; shared by replay and drill --device.
int finish(const RunSetup& setup, geo::OutputDir& outDir, sim::Session& session, const sim::RunSummary& run,
           json extra, const std::string& forcesPath, const std::string& summaryPath, const std::string& surfacePath,
           const std::string& what, geo::OutputFile* recording = nullptr) {
  const geo::SurfaceMesh surface = session.multiResolutionSurface();
  geo::writeMesh(surface.toTriangleMesh(), surfacePath);
  json summary = runSummaryJson(run, session, setup.mesh, setup.mode, setup.tool, setup.voxelSizeMm, setup.levels);
  for (auto& item : extra.items()) summary[item.key()] = item.value();
  summary["surface_triangles"] = surface.triangleCount();
  json files = {{"forces", forcesPath}, {"summary", summaryPath}, {"surface", surfacePath}};
  if (summary.contains("recording_out")) files["recording"] = summary["recording_out"];
  summary.erase("recording_out");
  summary["files"] = files;
  const std::string empty = markEmptyRun(summary, run);
  geo::writeFileAtomically(summaryPath, summary.dump(2) + "\n");
  outDir.commit();
  if (recording) recording->commit();  // the run is complete: the new recording replaces the old
  if (setup.json) {
    std::cout << summary.dump(2, ' ', false, json::error_handler_t::replace) << "\n";
  } else {
    const json& f = summary["faults"];
    std::cout << what << ": " << run.steps << " steps, max force " << run.maxForceN << " N, removed "
              << run.removedVolumeMm3 << " mm3; device faults: nan " << f["nan"] << ", gaps " << f["gaps"]
              << ", jumps " << f["jumps"] << ", watchdog " << f["watchdog"] << "\n"
              << "wrote " << forcesPath << ", " << summaryPath << ", " << surfacePath << "\n";
  }
  if (!empty.empty()) return emptyExit(setup.mode == "replay" ? "replay" : "drill", setup.mesh, empty, setup.allowEmpty);
  return kExitOk;
}

}  // namespace

int runReplay(const ReplayCommandOptions& options) {
  // Everything that can be refused is refused before the work.
  checkRunOptions(options.bone, options.levels);
  const sim::ToolKind kind = sim::parseToolKind(options.tool);
  const sim::CouplingMode coupling = couplingFor(options.coupling, false);
  dev::Recording recording = dev::loadRecording(options.log);
  geo::OutputDir outDir = openOutDir(options.outDir);
  const std::string forcesPath = options.outDir + "/forces.csv";
  const std::string summaryPath = options.outDir + "/summary.json";
  const std::string surfacePath = options.outDir + "/surface.ply";
  std::vector<std::string> inputs = options.bone.inputFiles();
  inputs.push_back(options.log);
  geo::refuseOverwritingInputs({forcesPath, summaryPath, surfacePath}, inputs);

  sim::Session session = openSession(options.bone, options.levels, kind, coupling);
  const std::size_t rows = recording.rows.size();
  dev::ReplayDevice device("replay:" + options.log, std::move(recording));
  sim::ForceLogWriter forces(forcesPath, coupling == sim::CouplingMode::Proxy);
  sim::DeviceRunOptions ro;
  ro.onRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  const sim::DeviceRunResult r = sim::runDevice(session, device, ro);
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place
  forces.commit();

  RunSetup setup{options.bone.input, sim::toolKindName(kind), *options.bone.voxelSizeMm, options.levels,
                 options.outDir, options.json, "replay", options.allowEmpty};
  json extra = {{"faults", faultsJson(r.safety.faults)},
                {"safety", safetyJson(r.safety, ro.input.safety.forceLimitN)},
                {"recording", {{"file", options.log}, {"rows", rows}, {"start_s", r.startS}, {"end_s", r.endS},
                               {"steps_before_pose", r.stepsBeforePose}}}};
  return finish(setup, outDir, session, r.run.summary, extra, forcesPath, summaryPath, surfacePath,
                "replayed " + options.log);
}

int runDrillWithDevice(const DrillCommandOptions& options) {
  checkRunOptions(options.bone, options.levels);
  const sim::ToolKind kind = sim::parseToolKind(options.tool);
  const sim::CouplingMode coupling = couplingFor(options.coupling, false);
  if (options.durationS && !(*options.durationS > 0.0 && *options.durationS <= sim::kMaxPathDurationS)) {
    std::ostringstream s;
    s << "--duration " << *options.durationS << ": must be a number of seconds in (0, " << sim::kMaxPathDurationS << "]";
    throw InputError(s.str());
  }
  // Every part of the name is parsed before any work (a bad name is exit 2 at once).
  for (std::size_t start = 0; start <= options.device.size();) {
    const std::size_t plus = options.device.find('+', start);
    const dev::DeviceName n =
        dev::parseDeviceName(options.device.substr(start, plus == std::string::npos ? std::string::npos : plus - start));
    if (n.kind == "mouse") {
      throw InputError("mouse: the viewer's device (fed by its window); the command line has no mouse "
                       "(use spacemouse, touch, replay:LOG.csv or scripted:...)");
    }
    if (plus == std::string::npos) break;
    start = plus + 1;
  }
  geo::OutputDir outDir = openOutDir(options.outDir);
  const std::string forcesPath = options.outDir + "/forces.csv";
  const std::string summaryPath = options.outDir + "/summary.json";
  const std::string surfacePath = options.outDir + "/surface.ply";
  std::vector<std::string> inputs = deviceInputs(options.device);
  for (const std::string& file : options.bone.inputFiles()) inputs.push_back(file);
  std::vector<std::string> outputs = {forcesPath, summaryPath, surfacePath};
  if (!options.record.empty()) {
    for (const std::string& out : outputs) {
      if (sameLexicalPath(options.record, out)) throw InputError("--record " + options.record + ": is also the run's " + out);
    }
    for (const std::string& in : inputs) {
      if (!in.empty() && sameLexicalPath(options.record, in)) {
        throw InputError("--record " + options.record + ": is an input of the run (it would be overwritten)");
      }
    }
    outputs.push_back(options.record);
  }
  geo::refuseOverwritingInputs(outputs, inputs);

  sim::Session session = openSession(options.bone, options.levels, kind, coupling);
  std::unique_ptr<dev::Device> device = sim::openSessionDevice(options.device, session);
  const dev::Capabilities caps = device->capabilities();
  if (!caps.pose) {
    throw InputError(options.device + ": gives no pose (buttons and pedal only); join it to a pose device, e.g. "
                                      "touch+" + options.device);
  }
  const bool deterministic = caps.timeDriven && !options.threaded;
  if (deterministic && options.durationS) {
    throw InputError("--duration: " + options.device + " ends with its path or recording (" +
                     std::to_string(caps.endS - caps.startS) + " s); --duration is for live devices");
  }
  if (!caps.timeDriven && !options.durationS) {
    throw InputError(options.device + ": a live device needs --duration S (how long to run, in seconds)");
  }

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

  sim::ForceLogWriter forces(forcesPath, coupling == sim::CouplingMode::Proxy);
  const auto logRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  sim::DeviceInputOptions io;
  io.frame = sim::defaultDeviceFrame(session);
  io.recorder = recorder ? &*recorder : nullptr;
  sim::RunSummary run;
  dev::SafetyStats safety;
  double limitN = io.safety.forceLimitN;
  if (caps.force && caps.maxForceN > 0.0) limitN = std::min(limitN, caps.maxForceN);
  json extra;
  if (deterministic) {
    sim::DeviceRunOptions ro;
    ro.input = io;
    ro.onRow = logRow;
    const sim::DeviceRunResult r = sim::runDevice(session, *device, ro);
    run = r.run.summary;
    safety = r.safety;
    extra["device"] = {{"name", options.device}, {"start_s", r.startS}, {"end_s", r.endS},
                       {"steps_before_pose", r.stepsBeforePose}};
  } else {
    sim::DeviceInput input(*device, io);
    sim::RuntimeOptions ro;
    // A recording runs for its length, whatever its stamps (DeviceInput shifts its clock).
    ro.durationS = options.durationS ? *options.durationS : caps.endS - caps.startS;
    ro.onRow = logRow;
    ro.keepLog = false;
    sim::RuntimeResult r;
    try {
      r = session.runThreaded(input, &input, ro);
    } catch (const sim::RuntimeFault& e) {  // one line: what failed, and where the rows logged are
      throw sim::RuntimeFault(std::string(e.what()) + "; " + forces.abandon());
    }
    run = r.run.summary;
    safety = input.safety().stats();
    extra["runtime"] = runtimeStatsJson(r.stats);
    extra["device"] = {{"name", options.device}, {"duration_s", ro.durationS},
                       {"frame_origin_mm", {io.frame.originMm.x, io.frame.originMm.y, io.frame.originMm.z}}};
  }
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place (its recording neither)
  forces.commit();
  if (recorder) {
    recorder->close();
    extra["recording_out"] = options.record;
    extra["device"]["recorded_rows"] = recorder->rows();
    extra["device"]["recording_dropped_rows"] = recorder->dropped();
  }
  extra["faults"] = faultsJson(safety.faults);
  extra["safety"] = safetyJson(safety, limitN);
  RunSetup setup{options.bone.input, sim::toolKindName(kind), *options.bone.voxelSizeMm, options.levels,
                 options.outDir, options.json, deterministic ? "device" : "device-threaded", options.allowEmpty};
  return finish(setup, outDir, session, run, extra, forcesPath, summaryPath, surfacePath,
                "drilled with " + options.device, recordFile ? &*recordFile : nullptr);
}

}  // namespace osteon::cli
