// A trial scored against its exercise's plan (score.h).
#include "osteon/simulation/score.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

namespace osteon::simulation {

TrialRecorder::TrialRecorder(std::size_t capacity) {
  samples_.reserve(capacity);
}

void TrialRecorder::add(const TrialSample& sample) noexcept {
  if (samples_.size() == samples_.capacity()) {
    ++dropped_;
    return;
  }
  samples_.push_back(sample);  // within the capacity reserved: no allocation
}

void TrialRecorder::add(double tS, const HapticStep& step, bool drillOn) noexcept {
  add(TrialSample{tS, step.proxy.tipMm, step.proxy.orientation, drillOn, step.magnitudeN,
                  step.clamped});
}

void TrialRecorder::clear() noexcept {
  samples_.clear();
  dropped_ = 0;
}

DeterministicOptions recordingOptions(TrialRecorder& recorder, double maxForceN,
                                      ProxyCoupling* coupling) {
  DeterministicOptions options;
  options.coupling = coupling;
  options.keepLog = false;
  // A step's row comes first (the force sent), then afterStep (the pose and the trigger).
  auto pending = std::make_shared<TrialSample>();
  options.onRow = [pending, maxForceN](const ForceLogRow& row) {
    pending->tS = row.tS;
    pending->tipMm = row.tipMm;
    pending->forceN = row.magnitudeN;
    pending->clamped = row.magnitudeN >= maxForceN * (1.0 - 1e-9);
  };
  options.afterStep = [pending, &recorder](std::size_t, const StepInput& input, const StepOutput&) {
    pending->orientation = input.pose.orientation;
    pending->drillOn = input.drillOn;
    recorder.add(*pending);
  };
  return options;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Time, travel, forces and where the tip went into the bone and how deep.
void scoreSamples(const Exercise& ex, const ExercisePlan& plan,
                  const std::vector<TrialSample>& samples, const geometry::VoxelGrid& before,
                  TrialScore& s) {
  if (samples.empty()) return;
  s.timeS = samples.back().tS - samples.front().tS;
  std::size_t entry = samples.size();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const TrialSample& x = samples[i];
    // Each sample stands for the time to the next (the last for its predecessor's).
    const double dtS = i + 1 < samples.size() ? samples[i + 1].tS - x.tS
                       : i > 0                ? x.tS - samples[i - 1].tS
                                              : 0.0;
    if (i > 0) s.pathLengthMm += glm::length(x.tipMm - samples[i - 1].tipMm);
    s.peakForceN = std::max(s.peakForceN, x.forceN);
    if (x.forceN > ex.forceLimitN) s.aboveForceLimitS += dtS;
    if (x.clamped) s.atClampS += dtS;
    if (entry == samples.size() && x.drillOn && fillFractionAt(before, x.tipMm) >= 0.5) entry = i;
  }
  if (entry == samples.size()) return;
  s.entered = true;
  // The surface crossing between the last sample outside and the first inside, by bisection.
  glm::dvec3 inside = samples[entry].tipMm;
  glm::dvec3 outside = entry > 0 ? samples[entry - 1].tipMm : inside;
  for (int k = 0; k < 40 && entry > 0; ++k) {
    const glm::dvec3 mid = 0.5 * (inside + outside);
    (fillFractionAt(before, mid) >= 0.5 ? inside : outside) = mid;
  }
  s.entryMm = inside;
  s.bottomMm = s.entryMm;
  // The hole is where the tool cut: its tip in the bone as it was (the proxy enters bone only by
  // cutting it), not where the tip went once withdrawn from the hole.
  for (std::size_t i = entry; i < samples.size(); ++i) {
    const double depthMm = glm::length(samples[i].tipMm - s.entryMm);
    if (depthMm > s.depthMm && fillFractionAt(before, samples[i].tipMm) >= 0.5) {
      s.depthMm = depthMm;
      s.bottomMm = samples[i].tipMm;
    }
  }
  s.entryErrorMm = glm::length(s.entryMm - plan.entryMm);
  s.depthVsPlanMm = s.depthMm - plan.depthMm;
  s.axisAngleErrorDeg =
      s.depthMm > 1e-9
          ? std::acos(
                std::clamp(glm::dot((s.bottomMm - s.entryMm) / s.depthMm, plan.axis), -1.0, 1.0)) *
                180.0 / M_PI
          : kNaN;
}

// The planned hole: the capsule the tip's sphere sweeps from outside the bone to full depth.
struct Hole {
  glm::dvec3 entry, axis, end;
  double depthMm, radiusMm;
  // Distance from the hole's axis segment (open towards the outside) minus the radius.
  double outsideBy(const glm::dvec3& p) const {
    const double along = glm::dot(p - entry, axis);
    const glm::dvec3 nearest = along <= depthMm ? entry + along * axis : end;
    return glm::length(p - nearest) - radiusMm;
  }
};

// True when bone lies within `mm` of c's outside (an empty voxel's centre that near).
bool nearSurface(const geometry::VoxelGrid& before, const glm::ivec3& v, double mm) {
  const double vs = before.voxelSizeMm();
  const int reach = int(std::ceil(mm / vs));
  for (int z = -reach; z <= reach; ++z)
    for (int y = -reach; y <= reach; ++y)
      for (int x = -reach; x <= reach; ++x) {
        if (double(x * x + y * y + z * z) * vs * vs > mm * mm) continue;
        if (before.fill(v + glm::ivec3(x, y, z)) < geometry::kFillHalf) return true;
      }
  return false;
}

struct ZoneSum {
  double mm3 = 0.0;
  glm::dvec3 weighted{0.0};
  void add(const glm::dvec3& c, double v) {
    mm3 += v;
    weighted += v * c;
  }
  NoGoBreach breach(const char* zone) const {
    return {zone, mm3, mm3 > 0.0 ? weighted / mm3 : glm::dvec3(0.0)};
  }
};

// Overcut, uncut and the no-go zones, voxel by voxel over the bricks either grid holds.
void scoreVolumes(const Exercise& ex, const ExercisePlan& plan, const geometry::VoxelGrid& before,
                  const geometry::VoxelGrid& after, TrialScore& s) {
  const double vs = before.voxelSizeMm();
  const double unitMm3 = before.voxelVolumeMm3() / double(geometry::kFillFull);
  const double reachMm = 0.5 * std::sqrt(3.0) * vs;  // a voxel's corners from its centre
  const Hole hole{plan.entryMm, plan.axis, plan.endMm, plan.depthMm, plan.radiusMm};
  const double farFromEntryMm = plan.depthMm + 2.0 * plan.radiusMm;
  ZoneSum cap, far;
  for (std::size_t b = 0; b < before.brickCount(); ++b) {
    if (!before.brickAllocated(b) && !after.brickAllocated(b) &&
        before.brickUniformFill(b) == after.brickUniformFill(b) && before.brickUniformFill(b) == 0)
      continue;
    const glm::ivec3 origin = before.brickCoord(b) * geometry::VoxelGrid::kBrickSize;
    for (int i = 0; i < geometry::VoxelGrid::kBrickVoxels; ++i) {
      constexpr int kEdge = geometry::VoxelGrid::kBrickSize;
      const glm::ivec3 v = origin + glm::ivec3(i % kEdge, (i / kEdge) % kEdge, i / (kEdge * kEdge));
      const double was = double(before.fill(v));
      if (was <= 0.0) continue;
      const double now = double(after.fill(v));
      const glm::dvec3 c = before.voxelCentreMm(v);
      const double outsideBy = hole.outsideBy(c);
      if (outsideBy <= -0.5 * vs) s.uncutMm3 += now * unitMm3;
      if (!(now < was)) continue;
      const double cutMm3 = (was - now) * unitMm3;
      s.removedMm3 += cutMm3;
      if (outsideBy > reachMm) s.overcutMm3 += cutMm3;
      if (ex.noGo.articularCap && plan.head) {
        const glm::dvec3 d = c - plan.head->centreMm;
        const double r = glm::length(d);
        const double cosCap = std::cos(ex.noGo.capHalfAngleDeg * M_PI / 180.0);
        if (r >= plan.head->radiusMm - ex.noGo.capDepthMm &&
            glm::dot(d, plan.head->axis) >= cosCap * r)
          cap.add(c, cutMm3);
      }
      if (ex.noGo.farCortex && glm::length(c - plan.entryMm) > farFromEntryMm &&
          nearSurface(before, v, ex.noGo.farCortexMm + 0.5 * vs))
        far.add(c, cutMm3);
    }
  }
  if (ex.noGo.articularCap) s.noGo.push_back(cap.breach("articular_cap"));
  if (ex.noGo.farCortex) s.noGo.push_back(far.breach("far_cortex"));
  for (const NoGoBreach& b : s.noGo) s.noGoMm3 += b.volumeMm3;
}

// Full weight within the limit, then linearly less to nothing at twice the limit.
double credit(const Criterion& c) {
  if (c.passed) return 1.0;
  if (!std::isfinite(c.value) || !(c.limit > 0.0)) return 0.0;
  return std::clamp(1.0 - (c.value - c.limit) / c.limit, 0.0, 1.0);
}

}  // namespace

TrialScore scoreTrial(const Exercise& ex, const ExercisePlan& plan,
                      const std::vector<TrialSample>& samples, const geometry::VoxelGrid& before,
                      const geometry::VoxelGrid& after) {
  TrialScore s;
  s.entryErrorMm = s.axisAngleErrorDeg = s.depthVsPlanMm = kNaN;
  scoreSamples(ex, plan, samples, before, s);
  scoreVolumes(ex, plan, before, after, s);
  const PassThresholds& p = ex.pass;
  s.criteria = {
      {"entry", s.entryErrorMm, "mm", p.entryMm, false, 20.0},
      {"angle", s.axisAngleErrorDeg, "deg", p.angleDeg, false, 20.0},
      {"depth", std::abs(s.depthVsPlanMm), "mm", p.depthMm, false, 15.0},
      {"overcut", s.overcutMm3, "mm3", p.overcutMm3, false, 10.0},
      {"no_go", s.noGoMm3, "mm3", p.noGoMm3, false, 20.0},
      {"force", s.aboveForceLimitS, "s", p.aboveForceLimitS, false, 10.0},
      {"time", s.timeS, "s", ex.timeLimitS, false, 5.0},
  };
  s.passed = true;
  double points = 0.0;
  for (Criterion& c : s.criteria) {
    c.passed = std::isfinite(c.value) && c.value <= c.limit;
    s.passed = s.passed && c.passed;
    points += c.weight * credit(c);
  }
  s.score = std::round(points * 10.0) / 10.0;
  return s;
}

TrialScore scoreSession(const Exercise& exercise, const ExercisePlan& plan, const Session& session,
                        const std::vector<TrialSample>& samples) {
  return scoreTrial(exercise, plan, samples, session.bone().grid(), session.grid());
}

std::string scoreJsonText(const TrialScore& s) {
  using nlohmann::json;
  const auto num = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  const auto vec = [](const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); };
  json criteria = json::array();
  for (const Criterion& c : s.criteria) {
    criteria.push_back({{"name", c.name},
                        {"value", num(c.value)},
                        {"unit", c.unit},
                        {"limit", c.limit},
                        {"passed", c.passed},
                        {"weight", c.weight}});
  }
  json noGo = json::array();
  for (const NoGoBreach& b : s.noGo) {
    noGo.push_back({{"zone", b.zone},
                    {"volume_mm3", b.volumeMm3},
                    {"where_mm", b.volumeMm3 > 0.0 ? vec(b.whereMm) : json(nullptr)}});
  }
  json out = {{"passed", s.passed},
              {"score", s.score},
              {"criteria", criteria},
              {"time_s", s.timeS},
              {"path_length_mm", s.pathLengthMm},
              {"entered", s.entered},
              {"entry_mm", s.entered ? vec(s.entryMm) : json(nullptr)},
              {"bottom_mm", s.entered ? vec(s.bottomMm) : json(nullptr)},
              {"entry_error_mm", num(s.entryErrorMm)},
              {"axis_angle_error_deg", num(s.axisAngleErrorDeg)},
              {"depth_mm", s.depthMm},
              {"depth_vs_plan_mm", num(s.depthVsPlanMm)},
              {"removed_mm3", s.removedMm3},
              {"overcut_mm3", s.overcutMm3},
              {"uncut_inside_mm3", s.uncutMm3},
              {"no_go", noGo},
              {"no_go_mm3", s.noGoMm3},
              {"peak_force_n", s.peakForceN},
              {"above_force_limit_s", s.aboveForceLimitS},
              {"at_clamp_s", s.atClampS}};
  return out.dump(2);
}

}  // namespace osteon::simulation
