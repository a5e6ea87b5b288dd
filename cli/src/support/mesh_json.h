// The "mesh" JSON object of info and voxelize: the file as read (format, faces triangulated or
// dropped) and its scale to mm.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "osteon/simulation/bone_source.h"

namespace osteon::cli {

nlohmann::json meshJson(const std::string& argument, const simulation::BoneMesh& loaded);

}  // namespace osteon::cli
