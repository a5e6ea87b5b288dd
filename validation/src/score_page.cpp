// The score page and its cut-away picture (score_page.h).
#include "osteon/validation/score_page.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <glm/geometric.hpp>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/image/image_writer.h"

namespace osteon::validation {

namespace sim = osteon::simulation;

namespace {

using Rgb = std::array<std::uint8_t, 3>;

double segmentDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

// The bone's colour at p: cut inside or outside the plan, or left, tinted in a no-go zone.
Rgb boneColour(const sim::Exercise& ex, const sim::ExercisePlan& plan,
               const geometry::VoxelGrid& before, const geometry::VoxelGrid& after,
               const glm::dvec3& p, const glm::dvec3& u, const glm::dvec3& v) {
  if (sim::fillFractionAt(before, p) < 0.5) return {38, 40, 48};
  const double along = glm::dot(p - plan.entryMm, plan.axis);
  const glm::dvec3 nearest = along <= plan.depthMm ? plan.entryMm + along * plan.axis : plan.endMm;
  const bool inPlan = glm::length(p - nearest) <= plan.radiusMm;
  if (sim::fillFractionAt(after, p) < 0.5) return inPlan ? Rgb{80, 190, 90} : Rgb{225, 60, 50};
  if (ex.noGo.articularCap && plan.head) {
    const glm::dvec3 d = p - plan.head->centreMm;
    const double r = glm::length(d);
    if (r >= plan.head->radiusMm - ex.noGo.capDepthMm &&
        glm::dot(d, plan.head->axis) >= std::cos(ex.noGo.capHalfAngleDeg * M_PI / 180.0) * r)
      return {160, 195, 240};
  }
  if (ex.noGo.farCortex && glm::length(p - plan.entryMm) > plan.depthMm + 2.0 * plan.radiusMm) {
    // The surface layer, judged in the picture's plane (eight directions).
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4.0;
      const glm::dvec3 q = p + ex.noGo.farCortexMm * (std::cos(a) * u + std::sin(a) * v);
      if (sim::fillFractionAt(before, q) < 0.5) return {200, 160, 230};
    }
  }
  return {232, 218, 185};
}

}  // namespace

std::vector<std::string> scorePageFiles(const std::string& folder) {
  return {folder + "/score.json", folder + "/score.html", folder + "/score.png"};
}

namespace {

// One square panel of the cut-away, in the plane through `centre` spanned by u (left to right)
// and v (up), into columns [x0, x0 + pixels) of an image `width` pixels wide.
void drawPanel(const sim::Exercise& ex, const sim::ExercisePlan& plan, const sim::TrialScore& score,
               const geometry::VoxelGrid& before, const geometry::VoxelGrid& after,
               const glm::dvec3& centre, const glm::dvec3& u, const glm::dvec3& v, int pixels,
               int x0, int width, std::vector<std::uint8_t>& rgb) {
  const double halfMm = std::max(20.0, 0.5 * plan.depthMm + 12.0);
  const double pixelMm = 2.0 * halfMm / pixels;
  for (int row = 0; row < pixels; ++row) {
    for (int col = 0; col < pixels; ++col) {
      const glm::dvec3 p =
          centre + (-halfMm + (col + 0.5) * pixelMm) * u + (halfMm - (row + 0.5) * pixelMm) * v;
      Rgb c = boneColour(ex, plan, before, after, p, u, v);
      const double along = glm::dot(p - plan.entryMm, plan.axis);
      const glm::dvec3 nearest =
          along <= plan.depthMm ? plan.entryMm + along * plan.axis : plan.endMm;
      if (std::abs(glm::length(p - nearest) - plan.radiusMm) < 0.6 * pixelMm && along > -8.0)
        c = {255, 255, 255};
      if (score.entered && segmentDistance(p, score.entryMm, score.bottomMm) < 0.8 * pixelMm)
        c = {230, 40, 230};
      if (glm::length(p - plan.entryMm) < 0.7) c = {250, 220, 40};
      if (score.entered && glm::length(p - score.entryMm) < 0.5) c = {230, 40, 230};
      const std::size_t at = (std::size_t(row) * std::size_t(width) + std::size_t(x0 + col)) * 3;
      std::copy(c.begin(), c.end(), rgb.begin() + std::ptrdiff_t(at));
    }
  }
}

// The plane of `axis` and the normal's part across it: u along the axis, v up.
void planeOf(const glm::dvec3& axis, const glm::dvec3& normal, glm::dvec3& u, glm::dvec3& v) {
  u = axis;
  v = normal - glm::dot(normal, u) * u;
  v = glm::length(v) > 1e-9 ? glm::normalize(v) : glm::normalize(glm::cross(u, {0.0, 0.0, 1.0}));
}

}  // namespace

std::vector<std::uint8_t> scoreCutaway(const sim::Exercise& ex, const sim::ExercisePlan& plan,
                                       const sim::TrialScore& score,
                                       const geometry::VoxelGrid& before,
                                       const geometry::VoxelGrid& after, int pixels) {
  const int width = 2 * pixels;
  std::vector<std::uint8_t> rgb(std::size_t(width) * std::size_t(pixels) * 3);
  glm::dvec3 u, v;
  planeOf(plan.axis, plan.normal, u, v);
  drawPanel(ex, plan, score, before, after, plan.entryMm + 0.5 * plan.depthMm * u, u, v, pixels, 0,
            width, rgb);
  // The hole drilled, in its own plane (the plan's again when the tool never entered).
  glm::dvec3 hole = plan.axis, from = plan.entryMm;
  if (score.entered && score.depthMm > 1e-6) {
    hole = (score.bottomMm - score.entryMm) / score.depthMm;
    from = score.entryMm;
  }
  planeOf(hole, plan.normal, u, v);
  drawPanel(ex, plan, score, before, after, from + 0.5 * plan.depthMm * u, u, v, pixels, pixels,
            width, rgb);
  for (int row = 0; row < pixels; ++row) {  // a divider
    const std::size_t at = (std::size_t(row) * std::size_t(width) + std::size_t(pixels)) * 3;
    std::fill(rgb.begin() + std::ptrdiff_t(at), rgb.begin() + std::ptrdiff_t(at + 3), 255);
  }
  return rgb;
}

namespace {

std::string html(const sim::Exercise& ex, const sim::TrialScore& s) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << ex.name
    << " score</title>\n<style>body{font-family:sans-serif;max-width:60em;margin:1em auto}"
       "td,th{padding:2px 10px;text-align:right}.fail{color:#c22}.pass{color:#282}"
       "img{float:right;width:420px;margin-left:1em}</style></head><body>\n";
  char line[256];
  std::snprintf(line, sizeof line, "<h1>%s: <span class=\"%s\">%s</span>, %.1f / 100</h1>\n",
                ex.name.c_str(), s.passed ? "pass" : "fail", s.passed ? "PASS" : "FAIL", s.score);
  h << line << "<p>" << ex.title << "</p>\n<img src=\"score.png\" alt=\"cut-away\">\n"
    << "<table><tr><th>criterion</th><th>value</th><th>limit</th><th></th></tr>\n";
  for (const sim::Criterion& c : s.criteria) {
    std::snprintf(line, sizeof line,
                  "<tr><td>%s</td><td>%.3f %s</td><td>%.3f</td><td class=\"%s\">%s</td></tr>\n",
                  c.name.c_str(), c.value, c.unit.c_str(), c.limit, c.passed ? "pass" : "fail",
                  c.passed ? "pass" : "FAIL");
    h << line;
  }
  std::snprintf(line, sizeof line,
                "</table>\n<p>time %.2f s, tip path %.1f mm; depth %.2f mm (%+.2f against the "
                "plan); removed %.1f mm&sup3;, outside the plan %.1f, left inside %.1f;",
                s.timeS, s.pathLengthMm, s.depthMm, s.depthVsPlanMm, s.removedMm3, s.overcutMm3,
                s.uncutMm3);
  h << line;
  for (const sim::NoGoBreach& b : s.noGo) {
    std::snprintf(line, sizeof line, " %s %.2f mm&sup3;", b.zone.c_str(), b.volumeMm3);
    h << line;
  }
  std::snprintf(line, sizeof line,
                "; peak force %.2f N, %.2f s above the limit, %.3f s at the clamp.</p>\n",
                s.peakForceN, s.aboveForceLimitS, s.atClampS);
  h << line
    << "<p>Cut-aways in the plane of the planned axis (left) and of the hole drilled (right): bone "
       "(beige), cut inside the plan "
       "(green), cut outside it (red), the cartilage cap (blue) and the far cortex (violet) "
       "no-go zones, the planned hole (white), the planned entry (yellow), the hole drilled "
       "(magenta).</p>\n</body></html>\n";
  return h.str();
}

}  // namespace

void writeScorePage(const std::string& folder, const sim::Exercise& exercise,
                    const sim::ExercisePlan& plan, const sim::TrialScore& score,
                    const geometry::VoxelGrid& before, const geometry::VoxelGrid& after) {
  constexpr int kPixels = 480;
  const std::vector<std::uint8_t> rgb = scoreCutaway(exercise, plan, score, before, after, kPixels);
  const std::string png = folder + "/score.png";
  const std::string error = image::writeImageU8(png, 2 * kPixels, kPixels, 3, rgb.data());
  if (!error.empty()) throw InputError(png + ": " + error);
  geometry::writeFileAtomically(folder + "/score.html", html(exercise, score));
}

}  // namespace osteon::validation
