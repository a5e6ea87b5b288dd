#include "scope.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace osteon::viewer {

namespace {
constexpr double kRadiansPerPixel = 0.004;

// The part of `v` perpendicular to unit `axis`, unit; `fallback`'s when v is along the axis.
glm::dvec3 perpendicular(const glm::dvec3& v, const glm::dvec3& axis, const glm::dvec3& fallback) {
  glm::dvec3 p = v - glm::dot(v, axis) * axis;
  if (glm::length(p) < 1e-6) p = fallback - glm::dot(fallback, axis) * axis;
  if (glm::length(p) < 1e-6) p = glm::cross(axis, glm::dvec3(1.0, 0.0, 0.0));
  if (glm::length(p) < 1e-6) p = glm::cross(axis, glm::dvec3(0.0, 1.0, 0.0));
  return glm::normalize(p);
}
}  // namespace

void Arthroscope::settleLensZero() {
  // Rotation 0 tilts the lens towards up on the screen, as a scope's light post up does.
  lensZero_ = perpendicular(upHint_, axis_, glm::dvec3(0.0, 1.0, 0.0));
}

void Arthroscope::aim(const glm::dvec3& tipMm, const glm::dvec3& lookAtMm, const glm::dvec3& upHint,
                      double portalBackMm) {
  tipMm_ = tipMm;
  upHint_ = glm::normalize(upHint);
  insertMm_ = std::clamp(portalBackMm, kMinInsertMm, kMaxInsertMm);
  const glm::dvec3 look = glm::normalize(lookAtMm - tipMm);
  // The shaft is the look direction tilted back by the lens angle, away from up.
  const glm::dvec3 side = perpendicular(upHint_, look, glm::dvec3(0.0, 1.0, 0.0));
  const double a = glm::radians(kLensAngleDeg);
  axis_ = glm::normalize(std::cos(a) * look - std::sin(a) * side);
  lensRad_ = 0.0;
  settleLensZero();
}

void Arthroscope::setShaft(const glm::dvec3& tipMm, const glm::dvec3& axis) {
  if (glm::length(axis) < 1e-9) return;
  tipMm_ = tipMm;
  axis_ = glm::normalize(axis);
  settleLensZero();
}

void Arthroscope::pivot(double dxPixels, double dyPixels) {
  const glm::dvec3 fulcrum = portal();
  const glm::dvec3 right = glm::normalize(glm::cross(viewDirection(), up()));
  const glm::dquat q = glm::angleAxis(-dxPixels * kRadiansPerPixel, up()) *
                       glm::angleAxis(-dyPixels * kRadiansPerPixel, right);
  axis_ = glm::normalize(q * axis_);
  tipMm_ = fulcrum + axis_ * insertMm_;
  settleLensZero();
}

void Arthroscope::insert(double mm) {
  const glm::dvec3 fulcrum = portal();
  insertMm_ = std::clamp(insertMm_ + mm, kMinInsertMm, kMaxInsertMm);
  tipMm_ = fulcrum + axis_ * insertMm_;
}

void Arthroscope::dimLight(double factor) {
  light_ = std::clamp(light_ * factor, 0.1, 3.0);
}

glm::dvec3 Arthroscope::viewDirection() const {
  const glm::dvec3 tilt = glm::angleAxis(lensRad_, axis_) * lensZero_;
  const double a = glm::radians(kLensAngleDeg);
  return glm::normalize(std::cos(a) * axis_ + std::sin(a) * tilt);
}

glm::dvec3 Arthroscope::up() const {
  return perpendicular(upHint_, viewDirection(), lensZero_);
}

glm::dmat4 Arthroscope::view() const {
  return glm::lookAt(tipMm_, tipMm_ + viewDirection(), up());
}

double Arthroscope::fovYDeg() {
  // The circle of kFieldDeg spans kFieldRadiusNdc of the height.
  return 2.0 * glm::degrees(std::atan(std::tan(0.5 * glm::radians(kFieldDeg)) / kFieldRadiusNdc));
}

glm::dmat4 Arthroscope::projection(double aspect) const {
  return glm::perspective(glm::radians(fovYDeg()), aspect, 0.5, 400.0);
}

ViewBasis Arthroscope::basis() const {
  const glm::dvec3 f = viewDirection(), u = up();
  return {tipMm_, f, glm::normalize(glm::cross(f, u)), u, fovYDeg()};
}

void aimAtWork(Arthroscope& scope, const glm::dvec3& pointMm, const glm::dvec3& outward,
               const glm::dvec3& toolForward) {
  const glm::dvec3 n = glm::normalize(outward);
  // Across from the handle: the handle's side (-forward) in the tangent plane, negated.
  const glm::dvec3 handle = -toolForward - glm::dot(-toolForward, n) * n;
  glm::dvec3 away = n;
  if (glm::length(handle) > 1e-6) away = glm::normalize(n - 0.8 * glm::normalize(handle));
  const glm::dvec3 superior(0.0, 0.0, 1.0);
  scope.aim(pointMm + 20.0 * away, pointMm, superior);
}

}  // namespace osteon::viewer
