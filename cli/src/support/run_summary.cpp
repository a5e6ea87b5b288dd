#include "support/run_summary.h"

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"
#include "support/output.h"

namespace osteon::cli {

namespace sim = osteon::simulation;
using nlohmann::json;

sim::CouplingMode couplingFor(const std::string& option, bool portalPath) {
  if (option.empty()) return portalPath ? sim::CouplingMode::Direct : sim::CouplingMode::Proxy;
  return sim::parseCouplingMode(option);
}

json runSummaryJson(const sim::RunSummary& s, const sim::Session& session, const std::string& mesh,
                    const std::string& mode, const std::string& tool, double voxelSizeMm,
                    int levels) {
  const sim::SessionOptions& so = session.options();
  json feel = {{"force_model", sim::forceModelKindName(so.forceModel)},
               {"rpm", so.settings.rpm},
               {"irrigation", so.settings.irrigation}};
  if (const sim::ThermalModel* heat = session.thermal()) {
    // The heat model's (the loops have stopped: its consumer side may be read here).
    feel["peak_temperature_c"] = heat->peakC();
    feel["damaged_bone_mm3"] = heat->damagedBoneVolumeMm3(session.grid());
  }
  json summary = {{"jitter_n", s.jitterN},
                  {"feel", feel},
                  {"coupling", sim::couplingModeName(s.coupling)},
                  {"max_gap_mm", s.maxGapMm},
                  {"max_step_change_n", s.maxStepChangeN},
                  {"max_force_n", s.maxForceN},
                  {"removed_volume_mm3", s.removedVolumeMm3},
                  {"haptic_step_us", percentilesJson(s.hapticStepUs)},
                  {"remesh_ms", percentilesJson(s.remeshMs)},
                  {"steps", s.steps},
                  {"degraded", sim::degraded(s)},
                  {"mode", mode},
                  {"mesh", mesh},
                  {"tool", tool},
                  {"voxel_size_mm", voxelSizeMm},
                  {"levels", levels},
                  {"finest_voxel_mm", session.simulation().finestVoxelMm()},
                  {"setup_ms", setupJson(session.setupTimings())},
                  {"peak_rss_mb", peakRssMb()}};
  for (const sim::DegradationCounter& c : sim::kDegradationCounters) {
    if (!c.runtimeOnly) summary[c.key] = c.count(s);
  }
  return summary;
}

std::string markEmptyRun(json& summary, const sim::RunSummary& s) {
  if (!(s.removedVolumeMm3 == 0.0 && s.maxForceN == 0.0)) return "";
  const std::string reason = "the path never meets bone (no contact, nothing removed)";
  summary["empty"] = true;
  summary["empty_reason"] = reason;
  return reason;
}

json runtimeStatsJson(const sim::RuntimeStats& st) {
  return {{"haptic_steps", st.hapticSteps},
          {"collision_steps", st.collisionSteps},
          {"haptic_overruns", st.hapticOverruns},
          {"collision_overruns", st.collisionOverruns},
          {"haptic_loop_us", percentilesJson(st.hapticStepUs)},
          {"visual_updates", st.visualUpdates},
          {"bricks_handed_over", st.bricksHandedOver},
          {"ring_full", st.ringFull},
          {"log_dropped", st.logDropped},
          {"haptic_standby_steps", st.standbySteps},
          {"realtime_priority", st.realtimeGranted}};
}

sim::RuntimeOptions threadedRunOptions() {
  sim::RuntimeOptions ro;
  const char* fault = std::getenv("OSTEON_INJECT_FAULT");
  if (!fault || !*fault) return ro;
  if (std::string(fault) != "surface-update") {
    throw InputError(std::string("OSTEON_INJECT_FAULT=") + fault +
                     ": unknown fault (known: surface-update)");
  }
  ro.beforeSurfaceUpdate = [] {
    throw std::runtime_error("injected fault (OSTEON_INJECT_FAULT=surface-update)");
  };
  return ro;
}

sim::RuntimeResult runThreadedLogged(sim::Session& session, sim::PoseSource& source,
                                     sim::ForceSink* sink, const sim::RuntimeOptions& options,
                                     sim::ForceLogWriter& forces, const IgtlCommandOptions& igtl,
                                     nlohmann::json& runtime) {
  try {
    IgtlServe serve(igtl, session);
    sim::RuntimeOptions served = options;
    serve.attach(served);
    const sim::RuntimeResult r = session.runThreaded(source, sink, served);
    runtime = runtimeStatsJson(r.stats);
    if (igtl.port) runtime["igtl"] = serve.finish();
    return r;
  } catch (const sim::RuntimeFault& e) {
    throw sim::RuntimeFault(std::string(e.what()) + "; " + forces.abandon());
  }
}

}  // namespace osteon::cli
