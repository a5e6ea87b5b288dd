// Scoring a trial of an exercise (exercise.h): what the tool did (samples over time) and what
// the bone lost (its fill before and after), against the plan. The same score for a CLI run
// of a recorded path (`osteon score`) and for the viewer's live session: the viewer keeps a
// TrialRecorder filled from its haptic loop (preallocated, no allocation there) and scores
// with scoreSession() at the end of the trial.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/exercise.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

// The fill fraction (0 empty, 1 full) at a point, trilinear between voxel centres.
inline double fillFractionAt(const geometry::VoxelGrid& grid, const glm::dvec3& pMm) {
  const glm::dvec3 g = grid.gridFromWorld(pMm) - 0.5;
  const glm::dvec3 base(std::floor(g.x), std::floor(g.y), std::floor(g.z));
  const glm::dvec3 f = g - base;
  const glm::ivec3 i0(base);
  double sum = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c & 1) != 0, (c & 2) != 0, (c & 4) != 0);
    const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z);
    if (w > 0.0) sum += w * double(grid.fill(i0 + o));
  }
  return sum / double(geometry::kFillFull);
}

// One sample of the tool, as the haptic loop saw it.
struct TrialSample {
  double tS = 0.0;
  glm::dvec3 tipMm{0.0};  // the simulated tool's tip (the proxy under proxy coupling)
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
  bool drillOn = false;
  double forceN = 0.0;   // the force sent to the hand
  bool clamped = false;  // that force was at N_max
};

// Samples kept in a buffer allocated up front: add() neither allocates, locks nor throws (call
// it from one thread; read samples() once that thread has stopped adding). Full: later samples
// are counted as dropped.
class TrialRecorder {
 public:
  explicit TrialRecorder(std::size_t capacity = 600000);  // ten minutes at 1 kHz
  void add(const TrialSample& sample) noexcept;
  void add(double tS, const HapticStep& step, bool drillOn) noexcept;
  void clear() noexcept;
  const std::vector<TrialSample>& samples() const { return samples_; }
  std::size_t dropped() const { return dropped_; }

 private:
  std::vector<TrialSample> samples_;
  std::size_t dropped_ = 0;
};

// The deterministic run's options that record every step's sample into `recorder` (afterStep
// and onRow are set; the other fields are the defaults, proxy coupling included when given).
DeterministicOptions recordingOptions(TrialRecorder& recorder, double maxForceN,
                                      ProxyCoupling* coupling);

// One pass / fail line of the score. Criteria, in order: entry (mm), angle (deg), depth (mm,
// |depth - plan|), overcut (mm3), no_go (mm3), force (s above the force limit), time (s).
struct Criterion {
  std::string name;
  double value = 0.0;  // NaN when it could not be measured (the tool never entered the bone)
  std::string unit;
  double limit = 0.0;  // passes at or below it
  bool passed = false;
  double weight = 0.0;  // its share of the score's 100 points
};

// Bone cut in one no-go zone.
struct NoGoBreach {
  std::string zone;  // "articular_cap", "far_cortex"
  double volumeMm3 = 0.0;
  glm::dvec3 whereMm{0.0};  // the centroid of what was cut there
};

struct TrialScore {
  bool passed = false;  // every criterion passed
  double score = 0.0;   // 0-100: each criterion's weight, in full within its limit, then
                        // falling linearly to nothing at twice the limit
  std::vector<Criterion> criteria;
  // The metrics the criteria come from, and more.
  double timeS = 0.0;              // first sample to last
  double pathLengthMm = 0.0;       // the tip's travel
  bool entered = false;            // the tip's centre went into the bone with the drill on
  glm::dvec3 entryMm{0.0};         // where it first did
  glm::dvec3 bottomMm{0.0};        // the deepest point it reached from there in the bone
  double entryErrorMm = 0.0;       // entry to the planned entry
  double axisAngleErrorDeg = 0.0;  // entry -> bottom against the planned axis
  double depthMm = 0.0;            // entry to bottom
  double depthVsPlanMm = 0.0;      // depthMm - planned (negative: too shallow)
  double removedMm3 = 0.0;         // all bone cut
  double overcutMm3 = 0.0;         // cut outside the planned hole
  double uncutMm3 = 0.0;           // left inside the planned hole
  std::vector<NoGoBreach> noGo;    // each zone checked, breached or not
  double noGoMm3 = 0.0;
  double peakForceN = 0.0;
  double aboveForceLimitS = 0.0;
  double atClampS = 0.0;
};

// The score from samples and the bone before and after (same grid geometry).
TrialScore scoreTrial(const Exercise& exercise, const ExercisePlan& plan,
                      const std::vector<TrialSample>& samples, const geometry::VoxelGrid& before,
                      const geometry::VoxelGrid& after);
// The same on a session as it is now: before is its bone's grid, after the drilled one.
TrialScore scoreSession(const Exercise& exercise, const ExercisePlan& plan, const Session& session,
                        const std::vector<TrialSample>& samples);

// The score as JSON text: passed, score, criteria [{name, value, unit, limit, passed}],
// then every metric above (docs/exercises.md).
std::string scoreJsonText(const TrialScore& score);

}  // namespace osteon::simulation
