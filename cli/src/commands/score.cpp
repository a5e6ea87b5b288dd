#include "commands/score.h"

#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "commands/drill.h"
#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/score.h"
#include "osteon/validation/score_page.h"
#include "support/output.h"

namespace osteon::cli {

namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

struct ScoreReport {
  std::string exercise, path;
  sim::TrialScore score;
  std::vector<std::string> files;
};

json toJson(const ScoreReport& r) {
  json j = json::parse(sim::scoreJsonText(r.score));
  j["exercise"] = r.exercise;
  j["path"] = r.path;
  j["files"] = r.files;
  return j;
}

void printText(const ScoreReport& r) {
  std::printf("%s on %s: %s, score %.1f / 100\n", r.path.c_str(), r.exercise.c_str(),
              r.score.passed ? "PASS" : "FAIL", r.score.score);
  for (const sim::Criterion& c : r.score.criteria) {
    std::printf("  %-8s %10.3f %-4s limit %8.3f  %s\n", c.name.c_str(), c.value, c.unit.c_str(),
                c.limit, c.passed ? "pass" : "FAIL");
  }
  for (const sim::NoGoBreach& b : r.score.noGo) {
    if (b.volumeMm3 > 0.0) {
      std::printf("  breach of %s: %.3f mm3 at (%.1f, %.1f, %.1f) mm\n", b.zone.c_str(),
                  b.volumeMm3, b.whereMm.x, b.whereMm.y, b.whereMm.z);
    }
  }
  std::printf("  time %.2f s, path %.1f mm, peak force %.2f N, at the clamp %.3f s\n",
              r.score.timeS, r.score.pathLengthMm, r.score.peakForceN, r.score.atClampS);
  std::string files;
  for (const std::string& f : r.files) files += (files.empty() ? "" : ", ") + f;
  std::printf("wrote %s\n", files.c_str());
}

}  // namespace

int runScore(const ScoreCommandOptions& options) {
  sim::Exercise exercise = sim::loadExercise(options.exercise);
  if (!options.up.empty()) exercise.bone.up = options.up;
  exercise.bone.check();
  if (!sim::isPathCsv(options.path)) {
    throw InputError(options.path + ": not a path CSV (a recording or `exercise plan`'s .csv)");
  }
  const sim::DrillPath path = sim::loadPathCsv(options.path);
  const std::string folder = options.outDir.empty() ? "." : options.outDir;
  const std::vector<std::string> pageFiles = validation::scorePageFiles(folder);
  std::vector<std::string> inputs = exercise.bone.inputFiles();
  inputs.push_back(options.path);
  if (!exercise.file.empty()) inputs.push_back(exercise.file);
  geometry::refuseOverwritingInputs(pageFiles, inputs);

  DrillCommandOptions drill;
  drill.bone = exercise.bone;
  drill.levels = exercise.levels;
  drill.path = options.path;
  drill.tool = sim::toolKindName(exercise.tool);
  drill.outDir = folder;
  drill.allowEmpty = true;  // a path that misses the bone is scored (and fails), not refused

  sim::TrialRecorder recorder(std::size_t(path.durationS() * 1000.0) + 2);
  sim::ToolOptions tool;
  const sim::DeterministicOptions recording =
      sim::recordingOptions(recorder, tool.maxForceN, nullptr);
  std::optional<sim::ExercisePlan> plan;
  ScoreReport r;
  r.exercise = exercise.name;
  r.path = options.path;
  DrillExtension extension;
  extension.printReport = false;
  extension.openBone = [&exercise](const sim::BoneSource& source) {
    return sim::openExerciseBone(exercise, source);
  };
  extension.sessionOptions = [&exercise](sim::SessionOptions& so) {
    so.toolOptions = sim::exerciseSessionOptions(exercise).toolOptions;
  };
  extension.opened = [&](sim::Session& session) { plan = sim::planExercise(exercise, session); };
  extension.onRow = recording.onRow;
  extension.afterStep = recording.afterStep;
  extension.done = [&](sim::Session& session) {
    r.score = sim::scoreSession(exercise, *plan, session, recorder.samples());
    geometry::writeFileAtomically(folder + "/score.json", sim::scoreJsonText(r.score) + "\n");
    validation::writeScorePage(folder, exercise, *plan, r.score, session.bone().grid(),
                               session.grid());
  };
  runDrill(drill, extension);
  r.files = pageFiles;
  printReport(r, options.json);
  return r.score.passed ? kExitOk : kExitCheckFailed;
}

}  // namespace osteon::cli
