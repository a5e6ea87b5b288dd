#include "commands/exercise.h"

#include <iostream>

#include <nlohmann/json.hpp>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/exercise.h"
#include "support/output.h"

namespace osteon::cli {

namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

struct ExerciseReport {
  std::string which;
  std::vector<sim::Exercise> exercises;  // list: every built-in; show, plan: the one
  std::optional<sim::ExercisePlan> plan;
  std::string out;
};

json planJson(const sim::ExercisePlan& p) {
  json j = {{"entry_mm", vec3Json(p.entryMm)}, {"normal", vec3Json(p.normal)},
            {"axis", vec3Json(p.axis)},        {"depth_mm", p.depthMm},
            {"diameter_mm", 2.0 * p.radiusMm}, {"end_mm", vec3Json(p.endMm)},
            {"duration_s", p.path.durationS()}};
  if (p.head) {
    j["head"] = {{"centre_mm", vec3Json(p.head->centreMm)},
                 {"radius_mm", p.head->radiusMm},
                 {"axis", vec3Json(p.head->axis)}};
  }
  if (p.farExitMm) j["far_exit_mm"] = vec3Json(*p.farExitMm);
  return j;
}

json toJson(const ExerciseReport& r) {
  if (r.which == "list") {
    json list = json::array();
    for (const sim::Exercise& e : r.exercises)
      list.push_back({{"name", e.name}, {"title", e.title}});
    return {{"exercises", list}};
  }
  json j = json::parse(sim::exerciseJsonText(r.exercises.front()));
  if (r.plan)
    j = {{"exercise", r.exercises.front().name}, {"plan", planJson(*r.plan)}, {"out", r.out}};
  return j;
}

void printText(const ExerciseReport& r) {
  if (r.which == "list") {
    for (const sim::Exercise& e : r.exercises) std::cout << e.name << "  " << e.title << "\n";
    return;
  }
  const sim::Exercise& e = r.exercises.front();
  if (!r.plan) {
    std::cout << e.name << ": " << e.title << "\n\n"
              << e.instructions << "\n\n"
              << sim::exerciseJsonText(e) << "\n";
    return;
  }
  const sim::ExercisePlan& p = *r.plan;
  std::cout << e.name << ": entry (" << p.entryMm.x << ", " << p.entryMm.y << ", " << p.entryMm.z
            << ") mm, axis (" << p.axis.x << ", " << p.axis.y << ", " << p.axis.z << "), "
            << p.depthMm << " mm deep, " << 2.0 * p.radiusMm << " mm wide\n";
  if (p.head) {
    std::cout << "  head centre (" << p.head->centreMm.x << ", " << p.head->centreMm.y << ", "
              << p.head->centreMm.z << ") mm, radius " << p.head->radiusMm << " mm\n";
  }
  std::cout << "wrote " << r.out << " (" << p.path.durationS() << " s)\n";
}

}  // namespace

int runExercise(const ExerciseCommandOptions& options) {
  ExerciseReport r;
  r.which = options.which;
  if (options.which == "list") {
    for (const std::string& name : sim::builtInExerciseNames())
      r.exercises.push_back(sim::loadExercise(name));
    printReport(r, options.json);
    return kExitOk;
  }
  sim::Exercise exercise = sim::loadExercise(options.exercise);
  if (!options.up.empty()) exercise.bone.up = options.up;
  exercise.bone.check();
  r.exercises.push_back(exercise);
  if (options.which == "plan") {
    if (!sim::isPathCsv(options.out))
      throw InputError("--out " + options.out + ": must be a .csv file");
    geometry::refuseOverwritingInputs({options.out}, exercise.bone.inputFiles());
    sim::Session session(sim::openExerciseBone(exercise, exercise.bone).bone,
                         sim::exerciseSessionOptions(exercise));
    r.plan = sim::planExercise(exercise, session);
    geometry::writeFileAtomically(options.out, sim::drillPathCsv(r.plan->path));
    r.out = options.out;
  }
  printReport(r, options.json);
  return kExitOk;
}

}  // namespace osteon::cli
