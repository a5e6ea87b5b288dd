// What a volume was read as (BoneRead::volume), as the commands that open one report it: the
// "volume" JSON object (its "transform" too) and two lines of text (what, and where).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "osteon/geometry/io/volume_io.h"

namespace osteon::cli {

// `meaning`: the volume options the user gave (an iso level given or the default).
nlohmann::json volumeJson(const geometry::VolumeLoad& volume,
                          const geometry::VolumeOptions& meaning);
// Empty for osteon's own grids (their output as it always was); else two lines (no final newline).
std::string volumeLine(const geometry::VolumeLoad& volume, const geometry::VolumeOptions& meaning);

}  // namespace osteon::cli
