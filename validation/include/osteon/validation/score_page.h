// A trial's score as a one-page HTML report with a cut-away picture of the hole against the
// plan (score.h): what `osteon score` writes beside score.json.
#pragma once

#include <string>
#include <vector>

#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/score.h"

namespace osteon::validation {

// The files a score's folder holds: score.json, score.html, score.png.
std::vector<std::string> scorePageFiles(const std::string& folder);

// The cut-away: two panels, the bone in the plane of the planned axis and the surface normal
// (left) and in the plane of the hole drilled (right), before and after (bone, cut inside the
// plan in green, outside it in red, the no-go zones tinted), the planned hole outlined in white,
// the planned entry in yellow and the hole drilled in magenta. RGB, top row first, 2 x pixels
// wide, `pixels` high.
std::vector<std::uint8_t> scoreCutaway(const simulation::Exercise& exercise,
                                       const simulation::ExercisePlan& plan,
                                       const simulation::TrialScore& score,
                                       const geometry::VoxelGrid& before,
                                       const geometry::VoxelGrid& after, int pixels);

// Writes score.html and score.png into `folder` (each complete or not at all). Throws
// InputError naming the file that cannot be written.
void writeScorePage(const std::string& folder, const simulation::Exercise& exercise,
                    const simulation::ExercisePlan& plan, const simulation::TrialScore& score,
                    const geometry::VoxelGrid& before, const geometry::VoxelGrid& after);

}  // namespace osteon::validation
