// `osteon score PATH.csv --exercise NAME|FILE`: a recorded or planned path drilled into the
// exercise's bone as `osteon drill` drills it, then scored against the plan (score.h): the
// score as text or JSON, and in --out-dir drill's files with score.json, score.html and the
// cut-away picture score.png. Exit 0 when the trial passes, 1 when it fails.
#pragma once

#include <string>

namespace osteon::cli {

struct ScoreCommandOptions {
  std::string path;      // the path CSV (a viewer recording, or `exercise plan`'s)
  std::string exercise;  // a built-in name or a .json file
  std::string up;        // the bone's up axis, over the exercise's
  std::string outDir = ".";
  bool json = false;
};

int runScore(const ScoreCommandOptions& options);

}  // namespace osteon::cli
