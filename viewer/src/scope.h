// The arthroscope (seed 3.1): a rigid scope through a portal, its lens angled 30 degrees off
// the shaft and turned about the shaft by the light post (the seed's rotation encoder), a
// circular field of view and a spotlight at its tip (the light encoder sets its brightness).
// It pivots about the portal, where it enters the skin, and slides in and out through it.
// Plain math, no GL: the app draws with its view and projection and masks the circle.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "camera.h"

namespace osteon::viewer {

class Arthroscope {
 public:
  static constexpr double kLensAngleDeg = 30.0;
  static constexpr double kFieldDeg = 75.0;  // the circular field, across
  static constexpr double kSpotHalfAngleDeg = 45.0;
  static constexpr double kMinInsertMm = 5.0;  // the tip stays past the portal
  static constexpr double kMaxInsertMm = 120.0;

  // Tip at `tipMm`, its lens (at rotation 0) looking at `lookAtMm`; `portalBackMm` behind the
  // tip along the shaft is the portal it pivots about; `upHint` is up on the screen.
  void aim(const glm::dvec3& tipMm, const glm::dvec3& lookAtMm, const glm::dvec3& upHint,
           double portalBackMm = 40.0);
  // A pose from a device: the tip and the shaft's direction (into the joint).
  void setShaft(const glm::dvec3& tipMm, const glm::dvec3& axis);

  // Mouse drags: the shaft swings about the portal (pixels; 0.004 rad each).
  void pivot(double dxPixels, double dyPixels);
  // In (> 0) or out along the shaft, kept within kMinInsertMm..kMaxInsertMm of the portal.
  void insert(double mm);
  // The lens about the shaft (the light post; radians, accumulates like the encoder).
  void rotateLens(double radians) { lensRad_ += radians; }
  void setLensRotation(double radians) { lensRad_ = radians; }
  double lensRotation() const { return lensRad_; }
  // The light source's setting, 0.1 .. 3.
  void dimLight(double factor);
  double light() const { return light_; }

  const glm::dvec3& tip() const { return tipMm_; }
  const glm::dvec3& axis() const { return axis_; }
  glm::dvec3 portal() const { return tipMm_ - axis_ * insertMm_; }
  // Where the angled lens looks: the shaft tilted kLensAngleDeg towards the light post.
  glm::dvec3 viewDirection() const;
  // Up on the screen: the camera head stays upright while the lens turns.
  glm::dvec3 up() const;
  glm::dmat4 view() const;
  glm::dmat4 projection(double aspect) const;
  // The vertical field of the projection (the circle fits inside it).
  static double fovYDeg();
  ViewBasis basis() const;
  // Radius of the circular field in normalized device coordinates (y); x is this / aspect.
  static constexpr double kFieldRadiusNdc = 0.96;

 private:
  glm::dvec3 tipMm_{0.0, 0.0, 50.0};
  glm::dvec3 axis_{0.0, 0.0, -1.0};  // unit, from the portal into the joint
  glm::dvec3 upHint_{0.0, 0.0, 1.0};
  glm::dvec3 lensZero_{0.0, 1.0, 0.0};  // unit, perpendicular to the axis: rotation 0's tilt
  double insertMm_ = 40.0;
  double lensRad_ = 0.0;
  double light_ = 1.0;
  void settleLensZero();
};

// The scope for a work site (a point on the bone, the outward normal there) and a tool coming
// in along `toolForward`: its tip 20 mm off the surface, across from the tool's handle (the
// triangulation of two portals), superior up, its lens looking at the point.
void aimAtWork(Arthroscope& scope, const glm::dvec3& pointMm, const glm::dvec3& outward,
               const glm::dvec3& toolForward);

}  // namespace osteon::viewer
