// The main view's cameras (orbit, arthroscope, follow), the picture-in-picture, and what each
// view draws: the bone, then the overlays, and for the arthroscope the black around its
// circular field.
#include "app.h"
#include "gl_util.h"  // epoxy before GLFW

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <cmath>
#include <cstdio>

namespace osteon::viewer {

namespace {

constexpr double kArrowMmPerN = 6.0;
constexpr double kLensRadPerKnobCount = 3.14159265358979 / 12.0;  // 15 degrees a detent
constexpr double kFollowDistanceMm = 70.0;
constexpr double kFollowSideDeg = 25.0;  // off the shaft, so the shaft does not hide the hole

glm::vec3 headlight(const ViewBasis& b) {
  return glm::vec3(glm::normalize(-b.forward + 0.4 * b.up - 0.3 * b.right));
}

}  // namespace

void App::aimScope() {
  const WorkSite& work = scene_->work();
  aimAtWork(scope_, work.pointMm, work.outward, scene_->initialPose().forward());
  scopeKnobSeen_ = false;
  // The follow camera: beside the tool's shaft, looking at its tip.
  follow_.frame(scene_->boundsMin(), scene_->boundsMax());
  const glm::dvec3 f = scene_->initialPose().forward();
  const glm::dvec3 up =
      std::abs(f.z) < 0.95 ? glm::dvec3(0.0, 0.0, 1.0) : glm::dvec3(0.0, 1.0, 0.0);
  const glm::dvec3 side = glm::normalize(glm::cross(f, up));
  const double a = glm::radians(kFollowSideDeg);
  follow_.setOrientation(lookOrientation(std::cos(a) * f + std::sin(a) * side, up));
  follow_.setDistance(kFollowDistanceMm);
  follow_.setTarget(scene_->initialPose().tipMm);
}

void App::updateCameras() {
  const simulation::DisplayState& d = scene_->live().display();
  follow_.setTarget(d.tS >= 0.0 ? d.pose.tipMm : target_.tipMm);
  glm::dvec3 tip(0.0), axis(0.0);
  std::int64_t knob = 0;
  if (!scene_->pollScope(d.tS, tip, axis, knob)) return;
  scope_.setShaft(tip, axis);
  if (!scopeKnobSeen_) {
    scopeKnob0_ = knob;
    scopeKnobSeen_ = true;
  }
  scope_.setLensRotation(double(knob - scopeKnob0_) * kLensRadPerKnobCount);
}

FrameCamera App::cameraFor(CameraMode mode, int width, int height) const {
  const double aspect = double(std::max(width, 1)) / double(std::max(height, 1));
  FrameCamera c;
  if (mode == CameraMode::Scope) {
    c.viewProj = glm::mat4(scope_.projection(aspect) * scope_.view());
    c.eye = glm::vec3(scope_.tip());
    c.light = headlight(scope_.basis());
    c.spot = true;
    c.spotPos = c.eye;
    c.spotDir = glm::vec3(scope_.viewDirection());
    c.spotCos = float(std::cos(glm::radians(Arthroscope::kSpotHalfAngleDeg)));
    c.spotGain = float(0.95 * scope_.light());
    return c;
  }
  const OrbitCamera& orbit = mode == CameraMode::Follow ? follow_ : camera_;
  c.viewProj = glm::mat4(orbit.projection(aspect) * orbit.view());
  c.eye = glm::vec3(orbit.eye());
  c.light = headlight(orbit.basis());
  return c;
}

ViewBasis App::viewBasis() const {
  switch (panel_.cameraMode) {
    case CameraMode::Scope:
      return scope_.basis();
    case CameraMode::Follow:
      return follow_.basis();
    case CameraMode::Orbit:
      break;
  }
  return camera_.basis();
}

void App::drawBone(const FrameCamera& camera) {
  renderer_->draw(camera, panel_.view, panel_.method, panel_.wire);
}

void App::drawOverlays(const FrameCamera& camera, const simulation::ToolPose& pose,
                       const simulation::ToolPose& commanded) {
  const simulation::DisplayState& d = scene_->live().display();
  if (panel_.view == View::Hierarchy && hierarchy_.ready()) {
    std::vector<glm::vec3> lines;
    const std::size_t drawn = hierarchy_.linesAround(panel_.hierarchyLevel, pose.tipMm,
                                                     panel_.hierarchyRadiusMm, 4000, lines);
    const DphBoxes& b = *hierarchy_.boxes();
    char text[160];
    std::snprintf(text, sizeof text, "%zu boxes at level %d of %d; %zu voxels, built in %.0f ms",
                  drawn, panel_.hierarchyLevel, hierarchy_.levelCount(), b.voxels, b.buildMs);
    panel_.hierarchyMessage = text;
    overlay_->drawLines(camera, lines, glm::vec4(0.3f, 0.9f, 1.0f, 0.8f));
  }
  drawPlan(camera);
  if (panel_.showTool) {
    overlay_->drawTool(camera, scene_->tool(), pose, d.drillOn);
    overlay_->drawArrow(camera, pose.tipMm, d.contact.forceN * kArrowMmPerN,
                        glm::vec4(0.95f, 0.9f, 0.2f, 1.0f));
    // Translucent, after everything opaque: where the hand is, when bone holds the tool back.
    if (toolView_.ghostLast) overlay_->drawGhost(camera, scene_->tool(), commanded, pose);
  }
}

void App::drawPictureInPicture(const simulation::ToolPose& pose,
                               const simulation::ToolPose& commanded) {
  const int side = std::max(64, std::min(width_, height_) * 2 / 5);
  const int x = width_ - side - 12, y = height_ - side - 12;  // the top right corner
  const CameraMode mode =
      panel_.cameraMode == CameraMode::Scope ? CameraMode::Orbit : CameraMode::Scope;
  glEnable(GL_SCISSOR_TEST);
  glScissor(x - 2, y - 2, side + 4, side + 4);  // a thin frame around it
  glClearColor(0.55f, 0.57f, 0.6f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glViewport(x, y, side, side);
  glScissor(x, y, side, side);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const FrameCamera camera = cameraFor(mode, side, side);
  drawBone(camera);
  drawOverlays(camera, pose, commanded);
  if (mode == CameraMode::Scope) overlay_->drawFieldMask(1.0);
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, width_, height_);
}

void App::zoomAtCursor(double steps) {
  switch (panel_.cameraMode) {
    case CameraMode::Scope:
      scope_.insert(2.0 * steps);  // the wheel slides the scope in and out of its portal
      return;
    case CameraMode::Follow:
      follow_.zoom(steps);
      return;
    case CameraMode::Orbit:
      break;
  }
  int w = 0, h = 0;
  glfwGetWindowSize(window_.get(), &w, &h);
  w = std::max(w, 1);
  h = std::max(h, 1);
  const double ndcX = 2.0 * cursorX_ / double(w) - 1.0, ndcY = 1.0 - 2.0 * cursorY_ / double(h);
  camera_.zoomAt(steps, ndcX, ndcY, double(w) / double(h));
}

void App::focusOnTool() {
  const simulation::DisplayState& d = scene_->live().display();
  const glm::dvec3 tip = d.tS >= 0.0 ? d.pose.tipMm : target_.tipMm;
  if (panel_.cameraMode == CameraMode::Follow) {
    follow_.setDistance(kFollowDistanceMm);
    return;
  }
  panel_.cameraMode = CameraMode::Orbit;
  camera_.setTarget(tip);
  camera_.setDistance(std::min(camera_.distance(), 2.0 * kFollowDistanceMm));
}

void App::cycleCamera() {
  CameraMode& m = panel_.cameraMode;
  m = m == CameraMode::Orbit ? CameraMode::Scope
                             : (m == CameraMode::Scope ? CameraMode::Follow : CameraMode::Orbit);
}

}  // namespace osteon::viewer
