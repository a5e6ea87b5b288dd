// `osteon drill`: one drilling run in the deterministic mode (seed 4): forces.csv,
// summary.json and the drilled surface.
#include "commands.h"
#include "run_summary.h"

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/core/memory.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/hierarchy/dph.h"
#include "osteon/geometry/io/mesh_io.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/io/volume_io.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace osteon::cli {

namespace geo = osteon::geometry;
namespace sim = osteon::simulation;
using nlohmann::json;

// commands.cpp: what a volume was read as.
json volumeJson(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning);
std::string volumeLine(const geo::VolumeLoad& v, const geo::VolumeOptions& meaning);

namespace {

json percentilesJson(const sim::Percentiles& p) { return {{"p50", p.p50}, {"p99", p.p99}, {"max", p.max}}; }

}  // namespace

json setupJson(const sim::SetupTimings& t) {
  return {{"load", t.loadMs},         {"voxelize", t.voxelizeMs},   {"density", t.densityMs},
          {"fine_fills", t.fineFillsMs}, {"hierarchy", t.hierarchyMs}, {"surface", t.surfaceMs},
          {"total", t.totalMs}};
}

std::string setupLine(const sim::SetupTimings& t, double pathMs) {
  char line[256];
  std::snprintf(line, sizeof line,
                "  set-up      %.0f ms: load %.0f, voxelize %.0f, density %.0f, fine fills %.0f, hierarchy %.0f, "
                "surface %.0f",
                t.totalMs, t.loadMs, t.voxelizeMs, t.densityMs, t.fineFillsMs, t.hierarchyMs, t.surfaceMs);
  std::string text = line;
  if (pathMs >= 0.0) {
    std::snprintf(line, sizeof line, ", path %.0f", pathMs);
    text += line;
  }
  std::snprintf(line, sizeof line, "; peak RSS %.0f MB", peakRssMb());
  return text + line;
}

sim::CouplingMode couplingFor(const std::string& option, bool portalPath) {
  if (option.empty()) return portalPath ? sim::CouplingMode::Direct : sim::CouplingMode::Proxy;
  return sim::parseCouplingMode(option);
}

json runSummaryJson(const sim::RunSummary& s, const sim::Session& session, const std::string& mesh,
                    const std::string& mode, const std::string& tool, double voxelSizeMm, int levels) {
  return {{"jitter_n", s.jitterN},
          {"coupling", sim::couplingModeName(s.coupling)},
          {"max_gap_mm", s.maxGapMm},
          {"clamp_steps", s.clampSteps},
          {"refine_steps_deferred", s.totals.stepsDeferred},
          {"refine_voxels_deferred", s.totals.voxelsDeferred},
          {"max_step_change_n", s.maxStepChangeN},
          {"max_force_n", s.maxForceN},
          {"removed_volume_mm3", s.removedVolumeMm3},
          {"haptic_step_us", percentilesJson(s.hapticStepUs)},
          {"remesh_ms", percentilesJson(s.remeshMs)},
          {"overruns", s.overruns},
          {"steps", s.steps},
          {"non_finite_forces", s.totals.nonFiniteForces},
          {"brick_allocations", s.totals.brickAllocations},
          {"cut_overflows", s.totals.cutOverflows},
          {"refine_pool_exhausted", s.totals.refinePoolExhausted},
          {"mask_overflows", s.totals.maskOverflows},
          {"mode", mode},
          {"mesh", mesh},
          {"tool", tool},
          {"voxel_size_mm", voxelSizeMm},
          {"levels", levels},
          {"finest_voxel_mm", session.simulation().finestVoxelMm()},
          {"setup_ms", setupJson(session.setupTimings())},
          {"peak_rss_mb", peakRssMb()}};
}

std::string markEmptyRun(json& summary, const sim::RunSummary& s) {
  if (!(s.removedVolumeMm3 == 0.0 && s.maxForceN == 0.0)) return "";
  const std::string reason = "the path never meets bone (no contact, nothing removed)";
  summary["empty"] = true;
  summary["empty_reason"] = reason;
  return reason;
}

json runtimeStatsJson(const sim::RuntimeStats& st) {
  return {{"haptic_steps", st.hapticSteps}, {"collision_steps", st.collisionSteps},
          {"haptic_overruns", st.hapticOverruns}, {"collision_overruns", st.collisionOverruns},
          {"haptic_loop_us", percentilesJson(st.hapticStepUs)},
          {"visual_updates", st.visualUpdates}, {"bricks_handed_over", st.bricksHandedOver},
          {"ring_full", st.ringFull}, {"log_dropped", st.logDropped},
          {"haptic_standby_steps", st.standbySteps}, {"realtime_priority", st.realtimeGranted}};
}

int runDrill(const DrillCommandOptions& options) {
  if (!options.device.empty()) return runDrillWithDevice(options);  // replay.cpp
  if (options.path.empty()) throw InputError("--path or --device: one is required (a path, or a device to drive the run)");
  if (options.durationS || !options.record.empty()) {
    throw InputError(std::string(options.durationS ? "--duration" : "--record") + ": only with --device");
  }
  // Everything that can be refused is refused before the work.
  sim::DrillingOptions drilling;
  drilling.levels = options.levels;
  sim::validateDrillingOptions(drilling);
  const sim::ToolKind kind = sim::parseToolKind(options.tool);
  const bool csvPath = sim::isPathCsv(options.path);
  const sim::CouplingMode coupling = couplingFor(options.coupling, !csvPath);
  options.bone.check();
  sim::DrillPath path;
  sim::Portal portal = sim::Portal::FiveOClock;
  if (csvPath) {
    path = sim::loadPathCsv(options.path);
  } else {
    portal = sim::parsePortal(options.path);
  }
  // The run's three files are one set: put in place together at the end (output_dir.h).
  geo::OutputDir outDir(options.outDir, {"forces.csv", "summary.json", "surface.ply"});
  const std::string forcesPath = options.outDir + "/forces.csv";
  const std::string summaryPath = options.outDir + "/summary.json";
  const std::string surfacePath = options.outDir + "/surface.ply";
  std::vector<std::string> inputs = options.bone.inputFiles();
  if (csvPath) inputs.push_back(options.path);
  geo::refuseOverwritingInputs({forcesPath, summaryPath, surfacePath}, inputs);

  sim::SessionOptions so;
  so.levels = options.levels;
  so.tool = kind;
  so.keepSurface = !options.threaded;  // the threaded runtime's visual thread keeps its own
  so.coupling = coupling;
  json volumeInfo;
  std::string volumeText;
  // Set-up, from the file to the first step: the session's stages plus the path (head fit and
  // portal plan), timed as one wall-clock total.
  const Clock::time_point setupStart = Clock::now();
  BoneSource source = options.bone;
  source.sampleFineFills = options.levels > 0;
  sim::OpenedBone opened = sim::BoneModel::open(source);
  if (opened.read.volume) {
    volumeInfo = volumeJson(*opened.read.volume, source.volume);
    volumeText = volumeLine(*opened.read.volume, source.volume);
  }
  sim::Session session(std::move(opened.bone), so);
  const Clock::time_point pathStart = Clock::now();
  json pathJson = {{"name", options.path}};
  if (!csvPath) {
    const sim::HumeralHead& head = session.humeralHead();
    const sim::PortalPlan plan = session.portalPath(portal);
    path = plan.path;
    pathJson["head_centre_mm"] = {head.centreMm.x, head.centreMm.y, head.centreMm.z};
    pathJson["head_radius_mm"] = head.radiusMm;
    pathJson["entry_mm"] = {plan.entryMm.x, plan.entryMm.y, plan.entryMm.z};
    pathJson["direction"] = {plan.direction.x, plan.direction.y, plan.direction.z};
    pathJson["speed_mm_per_s"] = plan.speedMmPerS;
  }
  pathJson["duration_s"] = path.durationS();
  const double pathMs = msSince(pathStart);
  sim::SetupTimings setup = session.setupTimings();
  setup.totalMs = msSince(setupStart);
  const double setupPeakRssMb = peakRssMb();  // ready for the first step; peak_rss_mb adds the run
  const std::size_t setupVoxels = session.hierarchy().voxelCount();  // every voxel with bone, before drilling

  // Streamed as the run goes (memory does not grow with the path), put in place when complete.
  sim::ForceLogWriter forces(forcesPath, coupling == sim::CouplingMode::Proxy);
  const auto logRow = [&forces](const sim::ForceLogRow& row) { forces.write(row); };
  sim::RunResult run;
  json runtimeJson;
  if (options.threaded) {
    sim::PathPoseSource device(path);
    sim::RuntimeOptions ro;
    ro.durationS = path.durationS();
    ro.onRow = logRow;
    ro.keepLog = false;
    sim::RuntimeResult r;
    try {
      r = session.runThreaded(device, nullptr, ro);
    } catch (const sim::RuntimeFault& e) {  // one line: what failed, and where the rows logged are
      throw sim::RuntimeFault(std::string(e.what()) + "; " + forces.abandon());
    }
    run = r.run;
    runtimeJson = runtimeStatsJson(r.stats);
  } else {
    sim::DeterministicOptions deterministic;
    deterministic.onRow = logRow;
    deterministic.keepLog = false;
    run = session.run(path, deterministic);
  }
  throwIfInterrupted();  // the run was cut short: nothing of it is put in place

  forces.commit();
  // The drilled bone with its refined regions, crack-free and smoothed, made once the run's
  // own surface is gone (its memory is what this extraction uses).
  session.releaseSurface();
  const geo::SurfaceMesh surface = session.multiResolutionSurface();
  geo::writeMesh(surface.toTriangleMesh(), surfacePath);

  const sim::RunSummary& s = run.summary;
  json summary = runSummaryJson(s, session, options.bone.input, options.threaded ? "threaded" : "deterministic",
                                sim::toolKindName(kind), *options.bone.voxelSizeMm, options.levels);
  summary["path"] = pathJson;
  summary["setup_ms"] = setupJson(setup);
  summary["setup_ms"]["path"] = pathMs;
  summary["setup_peak_rss_mb"] = setupPeakRssMb;
  summary["voxels"] = setupVoxels;
  summary["surface_triangles"] = surface.triangleCount();
  summary["files"] = {{"forces", forcesPath}, {"summary", summaryPath}, {"surface", surfacePath}};
  if (options.threaded) summary["runtime"] = runtimeJson;
  if (!volumeInfo.is_null()) summary["volume"] = volumeInfo;
  const std::string empty = markEmptyRun(summary, s);
  geo::writeFileAtomically(summaryPath, summary.dump(2) + "\n");
  outDir.commit();
  if (options.json) {
    std::cout << summary.dump(2, ' ', false, json::error_handler_t::replace) << "\n";
  } else {
    std::cout << "drilled " << options.path << " with the " << sim::toolKindName(kind) << " at "
              << *options.bone.voxelSizeMm << " mm, " << options.levels << " level(s): " << s.steps
              << " steps, max force " << s.maxForceN << " N, jitter " << s.jitterN << " N, removed "
              << s.removedVolumeMm3 << " mm3\n"
              << setupLine(setup, pathMs) << "\n"
              << "wrote " << forcesPath << ", " << summaryPath << ", " << surfacePath << "\n";
    if (!volumeText.empty()) std::cout << volumeText << "\n";
  }
  if (!empty.empty()) return emptyExit("drill", options.bone.input, empty, options.allowEmpty);
  return kExitOk;
}

}  // namespace osteon::cli
