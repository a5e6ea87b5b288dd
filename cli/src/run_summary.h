// The summary.json fields every drilling run shares (drill, drill --device, replay), so the
// three write the same names. Defined in drill.cpp; nlohmann/json stays out of this header
// but for its forward declarations.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>

namespace osteon::simulation {
enum class CouplingMode;
struct RunSummary;
struct RuntimeOptions;
struct RuntimeStats;
struct SetupTimings;
class Session;
}  // namespace osteon::simulation

namespace osteon::cli {

// jitter_n, coupling, max_gap_mm, max_step_change_n, max_force_n, removed_volume_mm3,
// haptic_step_us and remesh_ms {p50, p99, max}, steps, the degradation counters of runner.h
// (clamp_steps, refine_steps_deferred, overruns, non_finite_forces, ...) and "degraded" (any
// of them non-zero), mode, mesh, tool, voxel_size_mm, levels, finest_voxel_mm, and the
// session's setup_ms and peak_rss_mb (setupJson).
// --coupling as given, or its default when empty: direct for the seed's portal paths (their
// force logs stay the seed experiment's), proxy for everything a hand drives. Throws
// InputError naming a bad value.
simulation::CouplingMode couplingFor(const std::string& option, bool portalPath);

nlohmann::json runSummaryJson(const simulation::RunSummary& summary, const simulation::Session& session,
                              const std::string& mesh, const std::string& mode, const std::string& tool,
                              double voxelSizeMm, int levels);

// `setup_ms` {load, voxelize, density, fine_fills, hierarchy, surface, total} (stages a command
// does not run are 0), as drill, hierarchy, voxelize and mesh report their set-up.
nlohmann::json setupJson(const simulation::SetupTimings& setup);
// One line for the text output: "  set-up      812 ms: load 3, voxelize 410, ...; peak RSS 95 MB".
std::string setupLine(const simulation::SetupTimings& setup, double pathMs = -1.0);

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

}  // namespace osteon::cli
