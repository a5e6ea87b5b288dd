// What the runs driven by a device through the safety layer share (replay, drill --device):
// their checks and session, and how they finish (summary.json with the device's faults and the
// safety layer's work, the surface, the printed summary), written as `drill` writes its runs.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "osteon/devices/safety.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/coupling.h"
#include "osteon/simulation/device_input.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/session.h"
#include "osteon/simulation/tool.h"
#include "support/feel_options.h"
#include "support/files.h"
#include "support/igtl_serve.h"

namespace osteon::cli {

struct DeviceRunSetup {
  std::string mesh;
  std::string tool;
  double voxelSizeMm = 0.0;
  int levels = 2;
  bool json = false;
  std::string mode;  // replay, replay-threaded, device, device-threaded
  bool allowEmpty = false;
  bool printReport = true;  // false: the command prints its own (score)
};

// Levels and the bone's options, before any work.
void checkDeviceRunOptions(const simulation::BoneSource& bone, int levels);

// What a command that runs a device as replay does may change in its session (score): its
// options, and how its bone is opened (else BoneModel::open).
struct DeviceSessionHooks {
  std::function<void(simulation::SessionOptions&)> sessionOptions;
  std::function<simulation::OpenedBone(const simulation::BoneSource&)> openBone;
};

// The session a device run drills: the bone opened from its source, no kept surface (batch).
simulation::Session openDeviceRunSession(const simulation::BoneSource& bone, int levels,
                                         simulation::ToolKind kind,
                                         simulation::CouplingMode coupling,
                                         const FeelCommandOptions& feel,
                                         const DeviceSessionHooks& hooks = {});

// The files a device name reads (recordings, path CSVs), which no output may overwrite.
std::vector<std::string> deviceInputs(const std::string& name);
bool sameLexicalPath(const std::string& a, const std::string& b);

// A device run in real time on the threaded runtime (a live device, or a recording played at
// its own pace) for durationS: rows to `forces`; served over OpenIGTLink with --igtl.
struct ThreadedDeviceRun {
  simulation::RunSummary run;
  devices::SafetyStats safety;
  nlohmann::json runtime;  // the run's "runtime" object (with "igtl" when served)
};
ThreadedDeviceRun runDeviceThreaded(simulation::Session& session, devices::Device& device,
                                    const simulation::DeviceInputOptions& io, double durationS,
                                    simulation::ForceLogWriter& forces,
                                    const IgtlCommandOptions& igtl);

nlohmann::json faultsJson(const devices::FaultCounts& faults);
nlohmann::json safetyJson(const devices::SafetyStats& stats, double limitN);

// Writes summary.json (the run's shared fields, then `extra`) and the surface, puts the run's
// files (and a recording) in place, prints the summary; returns the exit code.
int finishDeviceRun(const DeviceRunSetup& setup, RunFolder& files, simulation::Session& session,
                    const simulation::RunSummary& run, nlohmann::json extra,
                    const std::string& what, geometry::OutputFile* recording = nullptr);

}  // namespace osteon::cli
