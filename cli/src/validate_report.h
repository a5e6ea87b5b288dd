// What `osteon validate` and `osteon validate --merge` share: writing report.json and
// report.html (validate.cpp); reading reports is report_reader.h.
#pragma once

#include "commands.h"
#include "report_reader.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace osteon::cli {

// The verdict (every crack-free case passes), the images, regressions against `old` (with
// --compare), then report.json and report.html into options.outDir.
void writeReport(nlohmann::json& report, const ValidateCommandOptions& options, const nlohmann::json& old,
                 const std::vector<std::string>& images);

// The closing line on stdout; the exit code of the verdict.
int printVerdict(const nlohmann::json& report, const std::string& outDir);

int runValidateMerge(const ValidateCommandOptions& options);  // validate_merge.cpp

}  // namespace osteon::cli
