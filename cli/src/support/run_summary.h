// The summary.json fields every drilling run shares (drill, drill --device, replay), so the
// three write the same names.
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "support/igtl_serve.h"

namespace osteon::simulation {
enum class CouplingMode;
struct RunSummary;
struct RuntimeOptions;
struct RuntimeStats;
struct RuntimeResult;
class ForceLogWriter;
class ForceSink;
class PoseSource;
class Session;
}  // namespace osteon::simulation

namespace osteon::cli {

// jitter_n, coupling, max_gap_mm, max_step_change_n, max_force_n, removed_volume_mm3,
// haptic_step_us and remesh_ms {p50, p99, max}, steps, the degradation counters of runner.h
// (clamp_steps, refine_steps_deferred, overruns, non_finite_forces, ...) and "degraded" (any
// of them non-zero), mode, mesh, tool, voxel_size_mm, levels, finest_voxel_mm, and the
// session's setup_ms and peak_rss_mb (setupJson).
nlohmann::json runSummaryJson(const simulation::RunSummary& summary,
                              const simulation::Session& session, const std::string& mesh,
                              const std::string& mode, const std::string& tool, double voxelSizeMm,
                              int levels);

// --coupling as given, or its default when empty: direct for the seed's portal paths (their
// force logs stay the seed experiment's), proxy for everything a hand drives. Throws
// InputError naming a bad value.
simulation::CouplingMode couplingFor(const std::string& option, bool portalPath);

// The empty-result rule of every drilling run (a path, a device, a recording): a run that
// never meets bone (nothing removed, no force at any step) is marked "empty": true with its
// reason in the summary; returns the reason ("" when bone was met). The caller then exits
// through emptyExit (1 unless --allow-empty).
std::string markEmptyRun(nlohmann::json& summary, const simulation::RunSummary& run);

// The threaded runtime's `runtime` object: steps and overruns per thread, visual updates, ...
nlohmann::json runtimeStatsJson(const simulation::RuntimeStats& stats);

// The threaded runtime's options for a drilling run, with the fault tests of the whole program
// inject: OSTEON_INJECT_FAULT=surface-update makes every visual surface update throw. Throws
// InputError for an unknown fault.
simulation::RuntimeOptions threadedRunOptions();

// session.runThreaded, its rows logged by `forces`: a RuntimeFault is told in one line that
// also says where the rows logged so far are. With --igtl the run is served over OpenIGTLink
// while it runs, and `runtime` (the run's "runtime" object) gets the link's "igtl" object.
simulation::RuntimeResult runThreadedLogged(
    simulation::Session& session, simulation::PoseSource& source, simulation::ForceSink* sink,
    const simulation::RuntimeOptions& options, simulation::ForceLogWriter& forces,
    const IgtlCommandOptions& igtl, nlohmann::json& runtime);

}  // namespace osteon::cli
