// What `osteon validate` and `osteon validate --merge` share: writing report.json and
// report.html (validate_report.cpp); reading reports is report_reader.h.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands/validate.h"
#include "osteon/validation/validate.h"
#include "report_reader.h"

namespace osteon::cli {

// One case of the run as report.json holds it.
nlohmann::json caseJson(const validation::ValidationCase& c);
// The machine, compiler and libraries the run used.
nlohmann::json environmentJson();

// The verdict (every crack-free case passes), the images, regressions against `old` (with
// --compare), then report.json and report.html into options.outDir.
void writeReport(nlohmann::json& report, const ValidateCommandOptions& options,
                 const nlohmann::json& old, const std::vector<std::string>& images);

// The closing line on stdout; the exit code of the verdict.
int printVerdict(const nlohmann::json& report, const std::string& outDir);

int runValidateMerge(const ValidateCommandOptions& options);  // validate_merge.cpp

}  // namespace osteon::cli
