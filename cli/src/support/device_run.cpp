#include "support/device_run.h"

#include <filesystem>
#include <iostream>

#include "osteon/core/error.h"
#include "osteon/geometry/io/mesh_io.h"
#include "support/output.h"
#include "support/run_summary.h"

namespace osteon::cli {

namespace dev = osteon::devices;
namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

void checkDeviceRunOptions(const sim::BoneSource& bone, int levels) {
  sim::DrillingOptions drilling;
  drilling.levels = levels;
  sim::validateDrillingOptions(drilling);
  bone.check();
}

sim::Session openDeviceRunSession(const sim::BoneSource& bone, int levels, sim::ToolKind kind,
                                  sim::CouplingMode coupling, const FeelCommandOptions& feel,
                                  const DeviceSessionHooks& hooks) {
  sim::BoneSource source = bone;
  source.sampleFineFills = levels > 0;
  sim::SessionOptions so;
  so.coupling = coupling;
  so.levels = levels;
  so.tool = kind;
  so.keepSurface = false;  // batch runs: the surface is extracted once at the end
  applyFeel(feel, so);
  if (hooks.sessionOptions) hooks.sessionOptions(so);
  return sim::Session((hooks.openBone ? hooks.openBone(source) : sim::BoneModel::open(source)).bone,
                      so);
}

ThreadedDeviceRun runDeviceThreaded(sim::Session& session, dev::Device& device,
                                    const sim::DeviceInputOptions& io, double durationS,
                                    sim::ForceLogWriter& forces, const IgtlCommandOptions& igtl) {
  sim::DeviceInput input(device, io);
  sim::RuntimeOptions ro = threadedRunOptions();
  ro.durationS = durationS;
  ro.onRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  ro.keepLog = false;
  ThreadedDeviceRun out;
  out.run = runThreadedLogged(session, input, &input, ro, forces, igtl, out.runtime).run.summary;
  out.safety = input.safety().stats();
  return out;
}

// The files a device name reads (recordings, path CSVs), which no output may overwrite.
std::vector<std::string> deviceInputs(const std::string& name) {
  std::vector<std::string> files;
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t plus = name.find('+', start);
    const std::string part =
        name.substr(start, plus == std::string::npos ? std::string::npos : plus - start);
    const std::size_t colon = part.find(':');
    if (colon != std::string::npos) {
      const std::string kind = part.substr(0, colon), argument = part.substr(colon + 1);
      if (kind == "replay" || (kind == "scripted" && sim::isPathCsv(argument)))
        files.push_back(argument);
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
  return {{"clamped_steps", s.clampedSteps},
          {"ramp_steps", s.rampSteps},
          {"held_steps", s.heldSteps},
          {"fault_steps", s.faultSteps},
          {"non_finite_forces", s.nonFiniteForces},
          {"engagements", s.engagements},
          {"max_force_n", s.maxForceN},
          {"max_step_change_n", s.maxStepChangeN},
          {"force_limit_n", limitN}};
}

namespace {

// The run as summary.json holds it, and the line of text that says it.
struct DeviceRunReport {
  json summary;
  sim::RunSummary run;
  std::string what;
};

json toJson(const DeviceRunReport& r) {
  return r.summary;
}

void printText(const DeviceRunReport& r) {
  const json& f = r.summary["faults"];
  const json& files = r.summary["files"];
  std::cout << r.what << ": " << r.run.steps << " steps, max force " << r.run.maxForceN
            << " N, removed " << r.run.removedVolumeMm3 << " mm3; device faults: nan " << f["nan"]
            << ", gaps " << f["gaps"] << ", jumps " << f["jumps"] << ", watchdog " << f["watchdog"]
            << "\n"
            << "wrote " << files["forces"].get<std::string>() << ", "
            << files["summary"].get<std::string>() << ", " << files["surface"].get<std::string>()
            << "\n";
}

}  // namespace

int finishDeviceRun(const DeviceRunSetup& setup, RunFolder& files, sim::Session& session,
                    const sim::RunSummary& run, json extra, const std::string& what,
                    geo::OutputFile* recording) {
  const geo::SurfaceMesh surface = session.multiResolutionSurface();
  geo::writeMesh(surface.toTriangleMesh(), files.surfacePath);
  DeviceRunReport r{runSummaryJson(run, session, setup.mesh, setup.mode, setup.tool,
                                   setup.voxelSizeMm, setup.levels),
                    run, what};
  json& summary = r.summary;
  summary["memory"] = memoryJson(session.memory());
  for (auto& item : extra.items()) summary[item.key()] = item.value();
  summary["surface_triangles"] = surface.triangleCount();
  json written = {
      {"forces", files.forcesPath}, {"summary", files.summaryPath}, {"surface", files.surfacePath}};
  if (summary.contains("recording_out")) written["recording"] = summary["recording_out"];
  summary.erase("recording_out");
  summary["files"] = written;
  const std::string empty = markEmptyRun(summary, run);
  geo::writeFileAtomically(files.summaryPath, summary.dump(2) + "\n");
  files.dir.commit();
  if (recording) recording->commit();  // the run is complete: the new recording replaces the old
  if (setup.printReport) printReport(r, setup.json);
  if (!empty.empty())
    return emptyExit(setup.mode == "replay" ? "replay" : "drill", setup.mesh, empty,
                     setup.allowEmpty);
  return kExitOk;
}

}  // namespace osteon::cli
