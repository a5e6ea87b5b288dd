// An exercise in the window: the plan drawn over the bone (the entry marker, the planned axis,
// a ring at the planned depth, the humeral head), the readouts against it each frame, and the
// trial scored through the same API as `osteon score` when it ends.
#include "app.h"
#include "gl_util.h"  // epoxy before GLFW

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <cmath>

namespace osteon::viewer {

namespace {

constexpr double kPi = 3.14159265358979;
// After a path's end, how long before its trial is scored (the last bricks land).
constexpr double kPathSettleS = 0.25;

// A circle of `radius` about `centre` in the plane normal to `axis`, as line segments.
void circle(const glm::dvec3& centre, const glm::dvec3& axis, double radius,
            std::vector<glm::vec3>& lines, int segments = 48) {
  const glm::dvec3 a = glm::normalize(axis);
  const glm::dvec3 helper = std::abs(a.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(a, helper)), v = glm::cross(a, u);
  for (int i = 0; i < segments; ++i) {
    const double t0 = 2.0 * kPi * i / segments, t1 = 2.0 * kPi * (i + 1) / segments;
    lines.push_back(glm::vec3(centre + radius * (std::cos(t0) * u + std::sin(t0) * v)));
    lines.push_back(glm::vec3(centre + radius * (std::cos(t1) * u + std::sin(t1) * v)));
  }
}

}  // namespace

void App::updateExercise(const simulation::ToolPose& pose) {
  const simulation::ExercisePlan* plan = scene_->plan();
  panel_.exercise = scene_->exercise();
  panel_.plan = plan;
  if (!plan) return;
  PlanReadouts& r = panel_.readouts;
  r.entryDistanceMm = glm::length(pose.tipMm - plan->entryMm);
  const double c = glm::dot(glm::normalize(pose.forward()), plan->axis);
  r.angleErrorDeg = glm::degrees(std::acos(std::clamp(c, -1.0, 1.0)));
  r.depthMm = glm::dot(pose.tipMm - plan->entryMm, plan->axis);
  const simulation::DisplayState& d = scene_->live().display();
  if (scene_->path() && !panel_.score && d.tS >= scene_->pathDurationS() + kPathSettleS)
    scoreTrial();
}

void App::scoreTrial() {
  if (!scene_->exercise() || panel_.score) return;
  panel_.score = scene_->scoreTrial();
  if (igtl_) {
    // Score: one line for Slicer's text node; ScoreDetails: the same JSON as `osteon score`.
    const simulation::TrialScore& s = *panel_.score;
    std::string line = std::string(s.passed ? "PASSED" : "FAILED") + ", score " +
                       std::to_string(int(std::lround(s.score))) + " / 100";
    std::string failed;
    for (const simulation::Criterion& c : s.criteria) {
      if (!c.passed) failed += (failed.empty() ? "" : ", ") + c.name;
    }
    if (!failed.empty()) line += " (failed: " + failed + ")";
    igtl_->sendString("Score", line);
    igtl_->sendString("ScoreDetails", simulation::scoreJsonText(s));
  }
}

void App::drawHeadAndEntry(const FrameCamera& camera) {
  // Without an exercise: the humeral head a portal was fitted to, and the portal's entry.
  const WorkSite& work = scene_->work();
  if (!work.head) return;
  const simulation::HumeralHead& h = *work.head;
  std::vector<glm::vec3> head;
  circle(h.centreMm, h.axis, h.radiusMm, head, 96);
  circle(h.centreMm, h.superior, h.radiusMm, head, 96);
  circle(h.centreMm, glm::cross(h.axis, h.superior), h.radiusMm, head, 96);
  glDisable(GL_DEPTH_TEST);
  overlay_->drawLines(camera, head, glm::vec4(0.55f, 0.75f, 1.0f, 0.3f));
  glEnable(GL_DEPTH_TEST);
  overlay_->drawMarker(camera, h.centreMm, 1.2, glm::vec4(0.55f, 0.75f, 1.0f, 1.0f));
  if (work.entry)
    overlay_->drawMarker(camera, work.pointMm, 0.9, glm::vec4(0.2f, 1.0f, 0.4f, 1.0f));
}

void App::drawPlan(const FrameCamera& camera) {
  const simulation::ExercisePlan* plan = scene_->plan();
  if (!panel_.showPlan) return;
  if (!plan) {
    drawHeadAndEntry(camera);
    return;
  }
  std::vector<glm::vec3> axis, ring, head;
  // The planned axis from 12 mm outside the entry to the planned depth.
  axis.push_back(glm::vec3(plan->entryMm - 12.0 * plan->axis));
  axis.push_back(glm::vec3(plan->endMm));
  // The depth ring at the hole's end, the entry ring at the surface.
  circle(plan->endMm, plan->axis, plan->radiusMm + 0.6, ring);
  circle(plan->entryMm, plan->axis, plan->radiusMm + 1.2, ring);
  if (plan->head) {
    // The fitted head: three great circles about its centre.
    const simulation::HumeralHead& h = *plan->head;
    circle(h.centreMm, h.axis, h.radiusMm, head, 96);
    circle(h.centreMm, h.superior, h.radiusMm, head, 96);
    circle(h.centreMm, glm::cross(h.axis, h.superior), h.radiusMm, head, 96);
  }
  glDisable(GL_DEPTH_TEST);  // the plan shows through the bone: it is where the hole goes
  overlay_->drawLines(camera, head, glm::vec4(0.55f, 0.75f, 1.0f, 0.35f));
  overlay_->drawLines(camera, axis, glm::vec4(0.25f, 1.0f, 0.45f, 0.95f));
  overlay_->drawLines(camera, ring, glm::vec4(1.0f, 0.8f, 0.2f, 0.95f));
  glEnable(GL_DEPTH_TEST);
  overlay_->drawMarker(camera, plan->entryMm, 0.9, glm::vec4(0.2f, 1.0f, 0.4f, 1.0f));
  if (plan->head)
    overlay_->drawMarker(camera, plan->head->centreMm, 1.2, glm::vec4(0.55f, 0.75f, 1.0f, 1.0f));
}

}  // namespace osteon::viewer
