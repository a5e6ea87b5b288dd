#include "camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace osteon::viewer {

namespace {
constexpr double kRadiansPerPixel = 0.005;
constexpr double kZoomPerStep = 0.9;
}  // namespace

const char* axisViewName(AxisView view) {
  switch (view) {
    case AxisView::Anterior:
      return "anterior";
    case AxisView::Posterior:
      return "posterior";
    case AxisView::Right:
      return "right";
    case AxisView::Left:
      return "left";
    case AxisView::Superior:
      return "superior";
    case AxisView::Inferior:
      return "inferior";
  }
  return "?";
}

glm::dquat lookOrientation(const glm::dvec3& forward, const glm::dvec3& up) {
  const glm::dvec3 back = -glm::normalize(forward);
  const glm::dvec3 right = glm::normalize(glm::cross(up, back));
  const glm::dvec3 trueUp = glm::cross(back, right);
  return glm::normalize(glm::quat_cast(glm::dmat3(right, trueUp, back)));
}

void OrbitCamera::frame(const glm::dvec3& lo, const glm::dvec3& hi) {
  target_ = 0.5 * (lo + hi);
  sceneRadius_ = std::max(0.5 * glm::length(hi - lo), 1e-3);
  // The bounding sphere fits the smaller of the two fields of view (aspect ~1.6 here).
  const double halfFov = 0.5 * glm::radians(kFovYDeg);
  distance_ = sceneRadius_ / std::sin(halfFov) * 1.05;
}

void OrbitCamera::setAxisView(AxisView view) {
  const glm::dvec3 z(0.0, 0.0, 1.0), anteriorUp(0.0, -1.0, 0.0);
  switch (view) {
    case AxisView::Anterior:
      orientation_ = lookOrientation({0.0, 1.0, 0.0}, z);
      break;
    case AxisView::Posterior:
      orientation_ = lookOrientation({0.0, -1.0, 0.0}, z);
      break;
    case AxisView::Right:
      orientation_ = lookOrientation({1.0, 0.0, 0.0}, z);
      break;
    case AxisView::Left:
      orientation_ = lookOrientation({-1.0, 0.0, 0.0}, z);
      break;
    case AxisView::Superior:
      orientation_ = lookOrientation({0.0, 0.0, -1.0}, anteriorUp);
      break;
    case AxisView::Inferior:
      orientation_ = lookOrientation({0.0, 0.0, 1.0}, anteriorUp);
      break;
  }
}

void OrbitCamera::rotate(double dxPixels, double dyPixels) {
  const glm::dquat yaw = glm::angleAxis(-dxPixels * kRadiansPerPixel, glm::dvec3(0.0, 0.0, 1.0));
  const glm::dquat pitch = glm::angleAxis(-dyPixels * kRadiansPerPixel, glm::dvec3(1.0, 0.0, 0.0));
  orientation_ = glm::normalize(yaw * orientation_ * pitch);
}

void OrbitCamera::pan(double dxPixels, double dyPixels, int viewportHeight) {
  const double mm = mmPerPixelAt(target_, viewportHeight);
  target_ += (-dxPixels * right() + dyPixels * up()) * mm;
}

void OrbitCamera::zoom(double steps) {
  distance_ = std::clamp(distance_ * std::pow(kZoomPerStep, steps), 1e-2 * sceneRadius_,
                         50.0 * sceneRadius_);
}

void OrbitCamera::zoomAt(double steps, double ndcX, double ndcY, double aspect) {
  const double before = distance_;
  zoom(steps);
  // The cursor's point on the target's plane, before and after: the target moves so it stays.
  const double halfH = std::tan(0.5 * glm::radians(kFovYDeg));
  const glm::dvec3 offset = (ndcX * aspect * halfH * right() + ndcY * halfH * up());
  target_ += offset * (before - distance_);
}

void OrbitCamera::magnify(double factor) {
  distance_ = std::clamp(distance_ / factor, 1e-2 * sceneRadius_, 50.0 * sceneRadius_);
}

glm::dmat4 OrbitCamera::view() const {
  const glm::dmat4 worldFromCamera =
      glm::translate(glm::dmat4(1.0), eye()) * glm::mat4_cast(orientation_);
  return glm::inverse(worldFromCamera);
}

glm::dmat4 OrbitCamera::projection(double aspect) const {
  // Nothing nearer than a twentieth of the distance to the target is shown: depth precision
  // at grazing folds decides whether a back face can win a pixel (the crack view counts them).
  const double nearMm = std::max(distance_ - 1.5 * sceneRadius_, 0.05 * distance_);
  const double farMm = distance_ + 1.5 * sceneRadius_;
  return glm::perspective(glm::radians(kFovYDeg), aspect, nearMm, farMm);
}

double OrbitCamera::mmPerPixelAt(const glm::dvec3& pointMm, int viewportHeight) const {
  return basis().mmPerPixelAt(pointMm, viewportHeight);
}

double ViewBasis::mmPerPixelAt(const glm::dvec3& pointMm, int viewportHeight) const {
  const double depth = std::max(glm::dot(pointMm - eye, forward), 1e-3);
  return 2.0 * depth * std::tan(0.5 * glm::radians(fovYDeg)) / double(std::max(viewportHeight, 1));
}

}  // namespace osteon::viewer
