// Reading validate reports that osteon did not just write: the old report of
// `validate --compare` and the shards' reports of `validate --merge`. A report is parsed with
// its nesting bounded, then every field the comparison, the merge and report.html read is
// checked for its type and range, here and only here: what passes is safe to use as it is.
// A library of its own (osteon_validate_reports), so tests/fuzz/fuzz_report_json.cpp runs
// this code.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace osteon::cli {

// A validate report nests 5 levels (report, cases, a case, portals, a portal); nlohmann's copy
// and dump recurse once per level, so a deeper file could exhaust the stack.
inline constexpr int kMaxReportDepth = 64;

// A report is a few MB at most (50 bones x 4 sizes: about 2 MB); the limit keeps memory bounded.
inline constexpr std::size_t kMaxReportBytes = std::size_t{256} << 20;

// Timings (a run's `seconds`, a case's `*_ms`) beyond a year are not a run's.
inline constexpr double kMaxRunSeconds = 366.0 * 24.0 * 3600.0;

// A JSON file of at most kMaxReportBytes and kMaxReportDepth levels. `what` leads every
// message ("--compare OLD.json", "--merge DIR"). Throws InputError.
nlohmann::json readReportJson(const std::string& path, const std::string& what);

// "model|voxel mm|method|mode" of a report.json case (validation/shard.h's caseKey).
std::string caseKey(const nlohmann::json& reportCase);

// The old report of --compare, read and checked before any work: a bad file after the run
// would lose the run. Throws InputError naming the file, and the case and field at fault.
nlohmann::json readComparable(const std::string& path);

struct ShardReport {
  std::string dir;
  nlohmann::json report;
  std::size_t index = 0, count = 0;
};

// A shard's report (reportPath, normally dir/report.json), checked for everything a merge
// relies on: its shard object, its cases, timings, and the images and plots it lists.
// Throws InputError("--merge DIR: ...").
ShardReport readShard(const std::string& dir, const std::string& reportPath);

// True for a path a report lists as one of its images or plots: under `folder` ("images",
// "plots"), of plain names only (letters, digits, '_', '-', '+', '.', no leading '.'), as
// validate writes them; so it is safe in report.html and stays inside the report's folder.
bool isReportOutputPath(const std::string& path, const std::string& folder);

}  // namespace osteon::cli
