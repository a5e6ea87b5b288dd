// The orbit camera: a target point, a distance and an orientation (camera to world, looking
// along its -z as OpenGL does). Plain math, no GL.
//
// Axis views in osteon's LPS frame (+x patient left, +y posterior, +z superior):
//   Anterior  looks along +y from -y, superior up: the patient's left on the screen's right
//   Posterior looks along -y;  Right looks along +x (from the patient's right, lateral for a
//   right humerus);  Left along -x;  Superior looks down -z and Inferior up +z, anterior up.
// The viewer starts in the anterior view, framed on the bone.
#pragma once

#include <algorithm>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace osteon::viewer {

enum class AxisView { Anterior, Posterior, Right, Left, Superior, Inferior };
const char* axisViewName(AxisView view);

// A view's axes, whichever camera gives them.
struct ViewBasis {
  glm::dvec3 eye{0.0}, forward{0.0, 0.0, -1.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0};
  double fovYDeg = 35.0;
  // Millimetres per pixel at a point's depth.
  double mmPerPixelAt(const glm::dvec3& pointMm, int viewportHeight) const;
};

class OrbitCamera {
 public:
  static constexpr double kFovYDeg = 35.0;

  // Centres on the box and backs off until it fits (with a margin); keeps the orientation.
  void frame(const glm::dvec3& lo, const glm::dvec3& hi);
  void setAxisView(AxisView view);
  // Mouse drags in pixels: turntable about world +z (superior) and pitch about the camera's
  // right axis.
  void rotate(double dxPixels, double dyPixels);
  // Moves the target with the cursor (pixels, in a viewport `viewportHeight` tall).
  void pan(double dxPixels, double dyPixels, int viewportHeight);
  // Wheel steps; positive zooms in.
  void zoom(double steps);
  // Divides the distance by `factor` (> 1 magnifies).
  void magnify(double factor);
  void setTarget(const glm::dvec3& targetMm) { target_ = targetMm; }
  void setOrientation(const glm::dquat& orientation) { orientation_ = orientation; }
  void setDistance(double mm) { distance_ = std::max(mm, 1e-3); }
  // Wheel steps towards the point under the cursor (x, y in [-1, 1], y up; aspect = w / h):
  // that point stays under the cursor, on the plane through the target facing the camera.
  void zoomAt(double steps, double ndcX, double ndcY, double aspect);
  ViewBasis basis() const { return {eye(), forward(), right(), up(), kFovYDeg}; }

  glm::dvec3 eye() const { return target_ - forward() * distance_; }
  glm::dvec3 forward() const { return orientation_ * glm::dvec3(0.0, 0.0, -1.0); }
  glm::dvec3 right() const { return orientation_ * glm::dvec3(1.0, 0.0, 0.0); }
  glm::dvec3 up() const { return orientation_ * glm::dvec3(0.0, 1.0, 0.0); }
  const glm::dvec3& target() const { return target_; }
  double distance() const { return distance_; }
  const glm::dquat& orientation() const { return orientation_; }

  glm::dmat4 view() const;
  // Near and far planes hug the framed bone (radius) so depth keeps its precision.
  glm::dmat4 projection(double aspect) const;
  // Millimetres per pixel at a point's depth.
  double mmPerPixelAt(const glm::dvec3& pointMm, int viewportHeight) const;

 private:
  glm::dvec3 target_{0.0};
  double distance_ = 200.0;
  double sceneRadius_ = 100.0;
  glm::dquat orientation_ = glm::dquat(1.0, 0.0, 0.0, 0.0);
};

// The orientation that looks along `forward` with `up` on top.
glm::dquat lookOrientation(const glm::dvec3& forward, const glm::dvec3& up);

}  // namespace osteon::viewer
