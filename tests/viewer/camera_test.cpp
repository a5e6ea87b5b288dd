// The orbit camera (viewer/src/camera.h): the wheel zooms towards the point under the cursor,
// which stays under it; an axis view turns about the target and keeps the zoom.
#include "camera.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace osteon::viewer {
namespace {

// Where a point lands in normalized device coordinates.
glm::dvec2 ndcOf(const OrbitCamera& camera, const glm::dvec3& pointMm, double aspect) {
  const glm::dvec4 clip = camera.projection(aspect) * camera.view() * glm::dvec4(pointMm, 1.0);
  return {clip.x / clip.w, clip.y / clip.w};
}

TEST(OrbitCameraTest, TheWheelZoomsTowardsThePointUnderTheCursor) {
  OrbitCamera camera;
  camera.setAxisView(AxisView::Anterior);
  camera.frame({-30.0, -30.0, -100.0}, {30.0, 30.0, 100.0});
  const double aspect = 1.6;
  const glm::dvec2 cursor(0.5, -0.3);
  // The point under the cursor on the plane through the target.
  const double halfH = std::tan(0.5 * glm::radians(OrbitCamera::kFovYDeg));
  const glm::dvec3 under =
      camera.target() +
      camera.distance() * halfH * (cursor.x * aspect * camera.right() + cursor.y * camera.up());
  ASSERT_NEAR(ndcOf(camera, under, aspect).x, cursor.x, 1e-9);
  const double before = camera.distance();
  for (int step = 0; step < 5; ++step) camera.zoomAt(1.0, cursor.x, cursor.y, aspect);
  EXPECT_LT(camera.distance(), 0.7 * before);
  const glm::dvec2 after = ndcOf(camera, under, aspect);
  EXPECT_NEAR(after.x, cursor.x, 1e-9);
  EXPECT_NEAR(after.y, cursor.y, 1e-9);
}

TEST(OrbitCameraTest, AnAxisViewKeepsTheZoomAndTheCentre) {
  OrbitCamera camera;
  camera.frame({-30.0, -30.0, -100.0}, {30.0, 30.0, 100.0});
  camera.zoomAt(4.0, 0.2, 0.1, 1.6);
  const glm::dvec3 target = camera.target();
  const double distance = camera.distance();
  camera.setAxisView(AxisView::Superior);
  EXPECT_EQ(camera.distance(), distance);
  EXPECT_EQ(camera.target(), target);
  EXPECT_NEAR(glm::dot(camera.forward(), glm::dvec3(0.0, 0.0, -1.0)), 1.0, 1e-12);
}

}  // namespace
}  // namespace osteon::viewer
