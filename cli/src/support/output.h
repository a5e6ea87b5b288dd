// How every command prints: one JSON object on stdout (--json), or lines of text; the JSON and
// text forms of what several commands share (set-up timings, percentiles, vectors), and the
// empty-result rule.
#pragma once

#include <string>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

namespace osteon::simulation {
struct Percentiles;
struct SetupTimings;
struct SessionMemory;
}  // namespace osteon::simulation

namespace osteon::cli {

nlohmann::json vec3Json(const glm::dvec3& v);
nlohmann::json ivec3Json(const glm::ivec3& v);
nlohmann::json percentilesJson(const simulation::Percentiles& p);  // {p50, p99, max}

// Paths are bytes, not always UTF-8: invalid sequences print as U+FFFD rather than failing.
void printJson(const nlohmann::json& j);

// `setup_ms` {load, voxelize, density, fine_fills, hierarchy, surface, total} (stages a command
// does not run are 0), as drill, hierarchy, voxelize and mesh report their set-up.
nlohmann::json setupJson(const simulation::SetupTimings& setup);
// What a session holds, by structure: {"voxels", "bytes": {...}, "bytes_per_voxel": {...}},
// the same keys in both (docs/performance.md, "Memory").
nlohmann::json memoryJson(const simulation::SessionMemory& memory);
// One line for the text output: "  set-up      812 ms: load 3, voxelize 410, ...; peak RSS 95 MB".
std::string setupLine(const simulation::SetupTimings& setup, double pathMs = -1.0);

// An empty result (no voxel inside, no triangles, a path that never meets bone): one line on
// stderr naming the command, the input and the reason; kExitCheckFailed unless allowEmpty.
int emptyExit(const char* command, const std::string& input, const std::string& reason,
              bool allowEmpty);

}  // namespace osteon::cli

namespace osteon::cli {

// A command's report, printed in the form asked for: toJson(report) as one JSON object, or
// printText(report) (both found by argument-dependent lookup, next to the report's struct).
template <typename Report>
void printReport(const Report& report, bool asJson) {
  if (asJson) {
    printJson(toJson(report));
  } else {
    printText(report);
  }
}

}  // namespace osteon::cli
