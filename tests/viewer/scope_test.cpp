// The arthroscope's geometry (viewer/src/scope.h): the lens looks 30 degrees off the shaft
// whichever way it is turned, aiming looks at the point asked for, the scope pivots about its
// portal, and the view's up stays upright while the lens turns.
#include "scope.h"

#include <algorithm>
#include <cmath>

#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

namespace osteon::viewer {
namespace {

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::degrees(
      std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)));
}

TEST(ArthroscopeTest, TheLensLooks30DegreesOffTheShaftAtEveryRotation) {
  Arthroscope scope;
  scope.aim({10.0, -40.0, 20.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0});
  // At rotation 0 it looks at the point.
  EXPECT_LT(angleDeg(scope.viewDirection(), glm::dvec3(0.0) - scope.tip()), 1e-9);
  glm::dvec3 first = scope.viewDirection();
  double widest = 0.0;
  for (int step = 0; step < 24; ++step) {
    scope.rotateLens(glm::radians(15.0));
    EXPECT_NEAR(angleDeg(scope.viewDirection(), scope.axis()), Arthroscope::kLensAngleDeg, 1e-9);
    widest = std::max(widest, angleDeg(scope.viewDirection(), first));
    // The image stays upright: up has no part along the view and leans towards +z.
    EXPECT_NEAR(glm::dot(scope.up(), scope.viewDirection()), 0.0, 1e-9);
    EXPECT_GT(scope.up().z, 0.0);
  }
  // Half a turn swings the view across the shaft: 60 degrees from where it started.
  EXPECT_NEAR(widest, 2.0 * Arthroscope::kLensAngleDeg, 1e-6);
  EXPECT_NEAR(angleDeg(scope.viewDirection(), first), 0.0, 1e-6);  // a whole turn back
}

TEST(ArthroscopeTest, ItPivotsAboutItsPortalAndSlidesThroughIt) {
  Arthroscope scope;
  scope.aim({0.0, -30.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 40.0);
  const glm::dvec3 portal = scope.portal();
  EXPECT_NEAR(glm::length(scope.tip() - portal), 40.0, 1e-9);
  scope.pivot(120.0, -80.0);
  EXPECT_LT(glm::length(scope.portal() - portal), 1e-9);
  EXPECT_NEAR(glm::length(scope.tip() - portal), 40.0, 1e-9);
  scope.insert(-10.0);
  EXPECT_NEAR(glm::length(scope.tip() - portal), 30.0, 1e-9);
  scope.insert(-1000.0);  // never out of the portal
  EXPECT_NEAR(glm::length(scope.tip() - portal), Arthroscope::kMinInsertMm, 1e-9);
  EXPECT_LT(glm::length(scope.portal() - portal), 1e-9);
}

// Aimed at a work site, the scope sits off the surface, across from the tool's handle, and
// sees the point (at the centre of its field).
TEST(ArthroscopeTest, AimedAtTheWorkItSitsAcrossFromTheTool) {
  Arthroscope scope;
  const glm::dvec3 point(5.0, -20.0, 30.0), outward(0.0, -1.0, 0.0);
  const glm::dvec3 toolForward = glm::normalize(glm::dvec3(-1.0, 1.0, 0.0));  // handle at +x
  aimAtWork(scope, point, outward, toolForward);
  EXPECT_GT(glm::dot(scope.tip() - point, outward), 5.0);
  EXPECT_LT(scope.tip().x, point.x);  // the handle's side is +x: the scope is on the other
  const glm::dvec4 clip = scope.projection(1.0) * scope.view() * glm::dvec4(point, 1.0);
  EXPECT_NEAR(clip.x / clip.w, 0.0, 1e-9);
  EXPECT_NEAR(clip.y / clip.w, 0.0, 1e-9);
}

}  // namespace
}  // namespace osteon::viewer
