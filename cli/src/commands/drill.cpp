#include "commands/drill.h"

#include <iostream>

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/core/memory.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"
#include "support/audio_out.h"
#include "support/files.h"
#include "support/output.h"
#include "support/run_summary.h"
#include "support/volume_report.h"

namespace osteon::cli {

namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

// What is refused before the work: the tool, the coupling, the path (a CSV read now, a portal
// planned on the bone once it is open), the bone's options.
struct DrillPlan {
  sim::ToolKind kind = sim::ToolKind::Drill;
  bool csvPath = false;
  sim::CouplingMode coupling = sim::CouplingMode::Direct;
  sim::DrillPath path;
  sim::Portal portal = sim::Portal::FiveOClock;
};

DrillPlan planDrill(const DrillCommandOptions& options) {
  if (options.path.empty()) {
    throw InputError("--path or --device: one is required (a path, or a device to drive the run)");
  }
  if (options.durationS || !options.record.empty()) {
    throw InputError(std::string(options.durationS ? "--duration" : "--record") +
                     ": only with --device");
  }
  checkIgtlOptions(options.igtl, options.threaded);
  sim::DrillingOptions drilling;
  drilling.levels = options.levels;
  sim::validateDrillingOptions(drilling);
  DrillPlan plan;
  plan.kind = sim::parseToolKind(options.tool);
  plan.csvPath = sim::isPathCsv(options.path);
  plan.coupling =
      checkFeel(options.feel, options.coupling, couplingFor(options.coupling, !plan.csvPath));
  options.bone.check();
  if (plan.csvPath) {
    plan.path = sim::loadPathCsv(options.path);
  } else {
    plan.portal = sim::parsePortal(options.path);
  }
  return plan;
}

// The run as summary.json holds it, and what only the text says.
struct DrillReport {
  const DrillCommandOptions* options = nullptr;
  json summary;
  sim::RunSummary run;
  sim::SetupTimings setup;
  double pathMs = 0.0;
  std::string volumeText;
  const RunFolder* files = nullptr;
};

json toJson(const DrillReport& r) {
  return r.summary;
}

void printText(const DrillReport& r) {
  const DrillCommandOptions& o = *r.options;
  const sim::RunSummary& s = r.run;
  std::cout << "drilled " << o.path << " with the " << r.summary["tool"].get<std::string>()
            << " at " << r.summary["voxel_size_mm"].get<double>() << " mm, " << o.levels
            << " level(s): " << s.steps << " steps, max force " << s.maxForceN << " N, jitter "
            << s.jitterN << " N, removed " << s.removedVolumeMm3 << " mm3\n"
            << setupLine(r.setup, r.pathMs) << "\n"
            << "wrote " << r.files->forcesPath << ", " << r.files->summaryPath << ", "
            << r.files->surfacePath << "\n";
  if (!r.volumeText.empty()) std::cout << r.volumeText << "\n";
}

// The portal planned on the bone (head fit, entry), or the CSV's path: the "path" object.
json planPath(DrillPlan& plan, const sim::Session& session, const std::string& name) {
  json pathJson = {{"name", name}};
  if (!plan.csvPath) {
    const sim::HumeralHead& head = session.humeralHead();
    const sim::PortalPlan portal = session.portalPath(plan.portal);
    plan.path = portal.path;
    pathJson["head_centre_mm"] = {head.centreMm.x, head.centreMm.y, head.centreMm.z};
    pathJson["head_radius_mm"] = head.radiusMm;
    pathJson["entry_mm"] = {portal.entryMm.x, portal.entryMm.y, portal.entryMm.z};
    pathJson["direction"] = {portal.direction.x, portal.direction.y, portal.direction.z};
    pathJson["speed_mm_per_s"] = portal.speedMmPerS;
  }
  pathJson["duration_s"] = plan.path.durationS();
  return pathJson;
}

// The path driven through the session, deterministic or threaded; its rows streamed to `forces`
// (memory does not grow with the path). `runtime` gets the threaded runtime's statistics.
sim::RunResult drive(sim::Session& session, const sim::DrillPath& path, bool threaded,
                     sim::ForceLogWriter& forces, json& runtime, const DrillExtension& extension,
                     const IgtlCommandOptions& igtl) {
  const auto logRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  if (!threaded) {
    sim::DeterministicOptions deterministic;
    deterministic.onRow = logRow;
    if (extension.onRow) {
      deterministic.onRow = [&forces, &extension](const sim::ForceLogRow& row) {
        forces.write(row);
        extension.onRow(row);
      };
    }
    deterministic.afterStep = extension.afterStep;
    deterministic.keepLog = false;
    return session.run(path, deterministic);
  }
  sim::PathPoseSource device(path);
  sim::RuntimeOptions ro = threadedRunOptions();
  ro.durationS = path.durationS();
  ro.onRow = logRow;
  ro.keepLog = false;
  return runThreadedLogged(session, device, nullptr, ro, forces, igtl, runtime).run;
}

}  // namespace

int runDrill(const DrillCommandOptions& options) {
  if (!options.device.empty()) return runDrillWithDevice(options);
  return runDrill(options, DrillExtension{});
}

int runDrill(const DrillCommandOptions& options, const DrillExtension& extension) {
  DrillPlan plan = planDrill(options);
  RunFolder files(options.outDir);
  std::vector<std::string> inputs = options.bone.inputFiles();
  if (plan.csvPath) inputs.push_back(options.path);
  geo::refuseOverwritingInputs({files.forcesPath, files.summaryPath, files.surfacePath}, inputs);
  AudioOut audio(options.audioOut, inputs);

  // Set-up, from the file to the first step: the session's stages plus the path (head fit and
  // portal plan), timed as one wall-clock total.
  const Clock::time_point setupStart = Clock::now();
  DrillReport r;
  r.options = &options;
  r.files = &files;
  sim::BoneSource source = options.bone;
  source.sampleFineFills = options.levels > 0;
  sim::OpenedBone opened =
      extension.openBone ? extension.openBone(source) : sim::BoneModel::open(source);
  json volume;
  if (opened.read.volume) {
    volume = volumeJson(*opened.read.volume, source.volume);
    r.volumeText = volumeLine(*opened.read.volume, source.volume);
  }
  sim::SessionOptions so;
  so.levels = options.levels;
  so.tool = plan.kind;
  so.keepSurface = !options.threaded;  // the threaded runtime's visual thread keeps its own
  so.coupling = plan.coupling;
  applyFeel(options.feel, so);
  if (extension.sessionOptions) extension.sessionOptions(so);
  sim::Session session(std::move(opened.bone), so);
  if (extension.opened) extension.opened(session);
  const Clock::time_point pathStart = Clock::now();
  const json pathJson = planPath(plan, session, options.path);
  r.pathMs = msSince(pathStart);
  r.setup = session.setupTimings();
  r.setup.totalMs = msSince(setupStart);
  const double setupPeakRssMb = peakRssMb();  // ready for the first step; peak_rss_mb adds the run
  const std::size_t setupVoxels =
      session.hierarchy().voxelCount();  // every voxel with bone, before drilling

  sim::ForceLogWriter forces(files.forcesPath, plan.coupling == sim::CouplingMode::Proxy,
                             calibrated(options.feel));
  audio.follow(forces);
  json runtime;
  r.run =
      drive(session, plan.path, options.threaded, forces, runtime, extension, options.igtl).summary;
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place
  forces.commit();
  audio.commit();
  if (extension.done) extension.done(session);
  // The drilled bone with its refined regions, crack-free and smoothed, made once the run's
  // own surface is gone (its memory is what this extraction uses).
  const sim::SessionMemory memory = session.memory();  // with the run's surface, before it goes
  session.releaseSurface();
  const geo::SurfaceMesh surface = session.multiResolutionSurface();
  geo::writeMesh(surface.toTriangleMesh(), files.surfacePath);

  r.summary = runSummaryJson(
      r.run, session, options.bone.input, options.threaded ? "threaded" : "deterministic",
      sim::toolKindName(plan.kind), session.grid().voxelSizeMm(), options.levels);
  r.summary["path"] = pathJson;
  // The first surface was extracted beside the first steps: its figures are known now.
  r.setup.surfaceMs = session.setupTimings().surfaceMs;
  r.setup.firstStepMs = session.setupTimings().firstStepMs;
  r.setup.surfaceReadyMs = session.setupTimings().surfaceReadyMs;
  r.summary["setup_ms"] = setupJson(r.setup);
  r.summary["setup_ms"]["path"] = r.pathMs;
  r.summary["setup_peak_rss_mb"] = setupPeakRssMb;
  r.summary["memory"] = memoryJson(memory);
  r.summary["voxels"] = setupVoxels;
  r.summary["surface_triangles"] = surface.triangleCount();
  r.summary["files"] = {
      {"forces", files.forcesPath}, {"summary", files.summaryPath}, {"surface", files.surfacePath}};
  if (options.threaded) r.summary["runtime"] = runtime;
  if (!volume.is_null()) r.summary["volume"] = volume;
  const std::string empty = markEmptyRun(r.summary, r.run);
  geo::writeFileAtomically(files.summaryPath, r.summary.dump(2) + "\n");
  files.dir.commit();
  if (extension.printReport) printReport(r, options.json);
  if (!empty.empty()) return emptyExit("drill", options.bone.input, empty, options.allowEmpty);
  return kExitOk;
}

}  // namespace osteon::cli
