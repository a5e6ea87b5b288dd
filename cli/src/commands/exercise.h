// `osteon exercise list|show NAME|plan NAME --out PATH.csv`: the exercises (built in, or JSON
// files; docs/exercises.md), one shown whole, and one's plan resolved against its bone with the
// ideal path written as a path CSV that `osteon drill --path` and `osteon score` read.
#pragma once

#include <string>

namespace osteon::cli {

struct ExerciseCommandOptions {
  std::string which;     // "list", "show" or "plan"
  std::string exercise;  // a built-in name or a .json file
  std::string out;       // plan: the path CSV
  std::string up;        // plan: the bone's up axis, over the exercise's
  bool json = false;
};

int runExercise(const ExerciseCommandOptions& options);

}  // namespace osteon::cli
