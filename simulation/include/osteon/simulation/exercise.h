// Exercises as data: a task on a bone (a suture-anchor hole from a portal), its plan and what
// passes, read from JSON (docs/exercises.md) or built in (`anchor-5`, `anchor-7` on the
// built-in humerus). Every front end opens one the same way:
//
//   Exercise ex = loadExercise("anchor-5");                // or a file: "my-task.json"
//   OpenedBone opened = BoneModel::open(ex.bone);
//   Session session(opened.bone, exerciseSessionOptions(ex));
//   ExercisePlan plan = planExercise(ex, session);         // entry, axis, head, ideal path
//   ... drill (a path, a device, a hand) ...
//   TrialScore s = scoreSession(ex, plan, session, samples);   // score.h
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/session.h"
#include "osteon/simulation/tool.h"

namespace osteon::simulation {

// Where the hole must not go. Both zones are judged on the bone as it was before the trial.
struct NoGoZones {
  // The articular cartilage cap: the part of the humeral head within capHalfAngleDeg of the
  // head axis (the middle of the articular surface), down to capDepthMm below the head sphere
  // (cartilage and subchondral plate). Breaking through it ruins the joint surface.
  bool articularCap = true;
  double capHalfAngleDeg = 25.0;
  double capDepthMm = 2.0;
  // The far cortex: bone within farCortexMm of the bone's outer surface, farther from the
  // planned entry than the planned hole reaches (its depth and diameter): a hole that goes
  // through the other side of the bone.
  bool farCortex = true;
  double farCortexMm = 2.0;
};

// The limits each criterion passes within (score.h names the criteria).
struct PassThresholds {
  double entryMm = 2.0;           // entry: actual entry to the planned entry
  double angleDeg = 10.0;         // angle: the hole's axis to the planned axis
  double depthMm = 2.0;           // depth: |hole depth - planned depth|
  double overcutMm3 = 15.0;       // overcut: bone cut outside the planned hole
  double noGoMm3 = 0.5;           // no_go: bone cut in the no-go zones
  double aboveForceLimitS = 1.0;  // force: time above Exercise::forceLimitN
  // time: the trial's duration within Exercise::timeLimitS
};

struct Exercise {
  std::string name;          // "anchor-5", or the file's stem
  std::string file;          // the JSON it was read from ("" for a built-in), for messages
  std::string title;         // one line
  std::string instructions;  // a paragraph for the trainee
  // The bone: a mesh, `default` or a volume, with its units, label or iso and voxel size (the
  // file's; else a mesh is voxelized at 1.2 mm, defaultVoxelSizeMm, and a volume keeps its own).
  BoneSource bone;
  int levels = 2;
  ToolKind tool = ToolKind::Drill;
  // The portal the hole is drilled from (seed 4's clock face on the head): it places the
  // planned entry unless entryMm is given.
  Portal portal = Portal::FiveOClock;
  // An explicit planned entry point (mm, projected onto the bone's surface): for bones whose
  // head osteon cannot find, and exercises off the clock face.
  std::optional<glm::dvec3> entryMm;
  // The planned axis. By default axisAngleDeg to the surface normal at the entry, the
  // "deadman" angle (Burkhart SS, The deadman theory of suture anchors: observations along a
  // south Texas fence line, Arthroscopy 11(1):119-123, 1995): the drill's tip is tilted from
  // the inward normal towards the tendon's pull, so its handle leans away from the pull and
  // the loaded suture pulls the anchor across its axis, never out along it. The rotator cuff
  // pulls from its footprint towards the glenoid, which the articular surface faces: the pull
  // is taken as the head axis, projected into the tangent plane at the entry.
  double axisAngleDeg = 45.0;
  std::optional<glm::dvec3> axis;  // an explicit direction of travel (any length but zero)
  double depthMm = 20.0;           // of the tip's centre past the entry, along the axis
  double diameterMm = 2.92;        // of the hole: the tool's tip diameter is set to it
  NoGoZones noGo;
  double forceLimitN = 3.0;  // force above this counts against the trial (N_max is 3.3 N)
  double timeLimitS = 60.0;  // the whole trial, first sample to last
  PassThresholds pass;
};

// The built-in exercises, in order: "anchor-5", "anchor-7".
std::vector<std::string> builtInExerciseNames();
// A built-in by name, or a JSON file. Throws InputError, one line naming the file (or the
// name) and the field: "ex.json: depth_mm: must be a positive number of mm".
Exercise loadExercise(const std::string& nameOrFile);
// The same from JSON text; `file` names it in messages.
Exercise parseExercise(const std::string& jsonText, const std::string& file);
// The exercise as JSON text (the schema parseExercise reads; every field written).
std::string exerciseJsonText(const Exercise& exercise);

// The exercise's bone opened from `source` (its bone, as a front end adjusted it): a refusal
// that names a bone option names it as the exercise's field ("ex.json: bone.voxel_size_mm 2:
// seg.nrrd has voxels of 1 mm ..."), not as a command-line flag the user never gave.
OpenedBone openExerciseBone(const Exercise& exercise, const BoneSource& source);

// The session an exercise is drilled in: its levels, its tool with the hole's diameter, and
// proxy coupling (bone stops the tool, as under a hand).
SessionOptions exerciseSessionOptions(const Exercise& exercise);

// The exercise resolved against the opened bone: where the hole goes, concretely.
struct ExercisePlan {
  glm::dvec3 entryMm{0.0};  // on the bone's surface
  glm::dvec3 normal{0.0};   // outward, at the entry
  glm::dvec3 axis{0.0};     // unit, the direction of travel into the bone
  double depthMm = 0.0;
  double radiusMm = 0.0;                // half the diameter
  glm::dvec3 endMm{0.0};                // the tip's centre at full depth
  std::optional<HumeralHead> head;      // the head sphere (none: explicit entry and axis)
  std::optional<glm::dvec3> farExitMm;  // where the axis, continued, leaves the bone
  // The ideal path: the approach with the cushion clear of the surface, the drill along the
  // axis to full depth at constant speed, a hold there and the way back out.
  DrillPath path;
};

// A straight hole as the plan drills it: from the cushion 1 mm clear of the surface along
// `axis` to `depthMm` past the entry at 2.5 mm/s with the drill on, a 1 s hold, 2 s back out.
DrillPath holePath(const glm::dvec3& entryMm, const glm::dvec3& axis, const glm::dvec3& normal,
                   double depthMm, double toolOuterRadiusMm);

// Throws InputError naming the bone when the plan needs a head the bone does not have (one
// line suggesting --up or an explicit entry point), or when the entry or axis are unusable.
ExercisePlan planExercise(const Exercise& exercise, const Session& session);

}  // namespace osteon::simulation
