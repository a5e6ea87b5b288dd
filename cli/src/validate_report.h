// What `osteon validate` and `osteon validate --merge` share: case keys, the --compare report,
// and writing report.json and report.html (validate.cpp).
#pragma once

#include "commands.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace osteon::cli {

// "model|voxel mm|method|mode" of a report.json case (validation/shard.h's caseKey).
std::string caseKey(const nlohmann::json& reportCase);

// The old report of --compare, read and checked before any work: a bad file after the run
// would lose the run. Throws InputError naming the file.
nlohmann::json readComparable(const std::string& path);

// The verdict (every crack-free case passes), the images, regressions against `old` (with
// --compare), then report.json and report.html into options.outDir.
void writeReport(nlohmann::json& report, const ValidateCommandOptions& options, const nlohmann::json& old,
                 const std::vector<std::string>& images);

// The closing line on stdout; the exit code of the verdict.
int printVerdict(const nlohmann::json& report, const std::string& outDir);

int runValidateMerge(const ValidateCommandOptions& options);  // validate_merge.cpp

}  // namespace osteon::cli
