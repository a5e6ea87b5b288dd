#include "commands/score.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "commands/drill.h"
#include "commands/replay.h"
#include "osteon/core/error.h"
#include "osteon/devices/recording.h"
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
  std::printf("  removed %.1f mm3, cut outside the plan %.1f mm3, left uncut inside it %.1f mm3\n",
              r.score.removedMm3, r.score.overcutMm3, r.score.uncutMm3);
  std::string files;
  for (const std::string& f : r.files) files += (files.empty() ? "" : ", ") + f;
  std::printf("wrote %s\n", files.c_str());
}

// A trial's file, told apart by its header and read whole: a device recording (what `drill
// --device ... --record` writes; replayed as `replay` does, its poses the tool's axis) or a
// path CSV (what `exercise plan` and the viewer write; drilled as `drill --path` does).
struct TrialFile {
  std::optional<sim::DrillPath> path;
  std::optional<devices::Recording> recording;
  double durationS = 0.0;
};

TrialFile readTrialFile(const std::string& file) {
  if (!sim::isPathCsv(file)) {
    throw InputError(file + ": not a path CSV or a device recording (.csv)");
  }
  std::string header;
  std::ifstream in(file);
  std::getline(in, header);
  const bool recording = header.rfind(devices::kRecordingHeaderWithoutSettings, 0) == 0;
  if (in && !recording && header.rfind("t,x,y,z,drill_on", 0) != 0) {
    throw InputError(file + ":1: header must be a path CSV's t,x,y,z,drill_on[,qw,qx,qy,qz] or " +
                     "a device recording's " + devices::kRecordingHeader);
  }
  TrialFile t;
  if (recording) {
    t.recording = devices::loadRecording(file);
    t.durationS = t.recording->endS() - t.recording->startS();
  } else {
    t.path = sim::loadPathCsv(file);
    t.durationS = t.path->durationS();
  }
  return t;
}

// The run of the trial in the exercise's session, with `extension`: a recording replayed, a path
// drilled, either written to `folder` as those commands write their runs.
void runTrial(const sim::Exercise& exercise, const std::string& file, TrialFile& trial,
              const std::string& folder, const DrillExtension& extension) {
  if (trial.recording) {
    ReplayCommandOptions replay;
    replay.log = file;
    replay.bone = exercise.bone;
    replay.levels = exercise.levels;
    replay.tool = sim::toolKindName(exercise.tool);
    replay.outDir = folder;
    replay.allowEmpty = true;  // a recording that misses the bone is scored (and fails)
    runReplay(replay, extension, &*trial.recording);
    return;
  }
  DrillCommandOptions drill;
  drill.bone = exercise.bone;
  drill.levels = exercise.levels;
  drill.path = file;
  drill.tool = sim::toolKindName(exercise.tool);
  drill.outDir = folder;
  drill.allowEmpty = true;  // a path that misses the bone is scored (and fails), not refused
  runDrill(drill, extension);
}

}  // namespace

int runScore(const ScoreCommandOptions& options) {
  sim::Exercise exercise = sim::loadExercise(options.exercise);
  if (!options.up.empty()) exercise.bone.up = options.up;
  exercise.bone.check();
  TrialFile trial = readTrialFile(options.path);
  const std::string folder = options.outDir.empty() ? "." : options.outDir;
  const std::vector<std::string> pageFiles = validation::scorePageFiles(folder);
  std::vector<std::string> inputs = exercise.bone.inputFiles();
  inputs.push_back(options.path);
  if (!exercise.file.empty()) inputs.push_back(exercise.file);
  geometry::refuseOverwritingInputs(pageFiles, inputs);

  sim::TrialRecorder recorder(std::size_t(trial.durationS * 1000.0) + 2);
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
  runTrial(exercise, options.path, trial, folder, extension);
  r.files = pageFiles;
  printReport(r, options.json);
  return r.score.passed ? kExitOk : kExitCheckFailed;
}

}  // namespace osteon::cli
