// The files a command writes: a drilling run's folder, and the refusal of inputs inside a folder
// a run fills with files of its own naming.
#pragma once

#include <string>
#include <vector>

#include "osteon/geometry/io/output_dir.h"

namespace osteon::cli {

// A drilling run's folder (drill, drill --device, replay): forces.csv, summary.json and
// surface.ply, one set put in place together at the end (output_dir.h).
struct RunFolder {
  explicit RunFolder(const std::string& folder);
  geometry::OutputDir dir;
  std::string forcesPath, summaryPath, surfacePath;
};

// Refuses (InputError) any existing input inside `folder`, which a command fills with files of
// its own naming (run logs, images).
void refuseInputsInside(const std::string& folder, const std::vector<std::string>& inputs);

}  // namespace osteon::cli
