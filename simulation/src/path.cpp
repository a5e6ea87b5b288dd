#include "osteon/simulation/path.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>

#include "osteon/core/error.h"
#include "osteon/core/input_file.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

namespace {

struct SphereFit {
  glm::dvec3 centre{0.0};
  double radius = 0.0;
  double rms = 0.0;
  int used = 0;
  glm::dvec3 pointsMean{0.0};  // of the points fitted: on a head, the articular cap's middle
  double areaMm2 = 0.0;        // of the surface the points fitted stand for (robustEndFit)
  bool ok = false;
};

// Algebraic least squares: |p|^2 = 2 c.p + k, r^2 = k + |c|^2 (Gaussian elimination with
// partial pivoting on the 4x4 normal equations).
SphereFit fitSphere(const std::vector<glm::dvec3>& points, const glm::dvec3& shift) {
  SphereFit fit;
  if (points.size() < 8) return fit;
  std::array<std::array<double, 5>, 4> m{};
  for (const glm::dvec3& q : points) {
    const glm::dvec3 p = q - shift;  // centred for conditioning
    const std::array<double, 4> row = {2 * p.x, 2 * p.y, 2 * p.z, 1.0};
    const double rhs = glm::dot(p, p);
    for (std::size_t i = 0; i < 4; ++i) {
      for (std::size_t j = 0; j < 4; ++j) m[i][j] += row[i] * row[j];
      m[i][4] += row[i] * rhs;
    }
  }
  for (std::size_t col = 0; col < 4; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < 4; ++r)
      if (std::abs(m[r][col]) > std::abs(m[pivot][col])) pivot = r;
    if (std::abs(m[pivot][col]) < 1e-12) return fit;
    std::swap(m[col], m[pivot]);
    for (std::size_t r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double f = m[r][col] / m[col][col];
      for (std::size_t c = col; c < 5; ++c) m[r][c] -= f * m[col][c];
    }
  }
  const glm::dvec3 c(m[0][4] / m[0][0], m[1][4] / m[1][1], m[2][4] / m[2][2]);
  const double k = m[3][4] / m[3][3];
  const double r2 = k + glm::dot(c, c);
  if (!(r2 > 0.0)) return fit;
  fit.centre = c + shift;
  fit.radius = std::sqrt(r2);
  double sum = 0.0;
  for (const glm::dvec3& p : points) {
    const double e = glm::length(p - fit.centre) - fit.radius;
    sum += e * e;
  }
  fit.rms = std::sqrt(sum / double(points.size()));
  fit.used = int(points.size());
  for (const glm::dvec3& p : points) fit.pointsMean += p / double(points.size());
  fit.ok = std::isfinite(fit.radius) && std::isfinite(fit.centre.x + fit.centre.y + fit.centre.z);
  return fit;
}

// Start from the end cap, then keep refitting to the points that lie on the sphere and face
// away from its centre: the shaft, neck and tuberosities fall away (their normals do not point
// radially from the head centre) and the articular sphere stays.
SphereFit robustEndFit(const std::vector<glm::dvec3>& points,
                       const std::vector<glm::dvec3>& normals, const std::vector<double>& areas,
                       const std::vector<double>& along, double capFrom, double regionFrom,
                       double sign) {
  std::vector<glm::dvec3> subset;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (sign * along[i] >= capFrom) subset.push_back(points[i]);
  SphereFit fit = fitSphere(subset, subset.empty() ? glm::dvec3(0.0) : subset.front());
  const double cosMax = std::cos(12.0 * M_PI / 180.0);
  for (int iteration = 0; iteration < 20 && fit.ok; ++iteration) {
    // The band follows the spread of the points kept so far, not of the whole region.
    std::vector<double> residuals;
    for (const glm::dvec3& p : subset)
      residuals.push_back(std::abs(glm::length(p - fit.centre) - fit.radius));
    if (residuals.empty()) break;
    const auto middle = residuals.begin() + std::ptrdiff_t(residuals.size() / 2);
    std::nth_element(residuals.begin(), middle, residuals.end());
    const double tolerance = std::max(0.005 * fit.radius, 2.0 * residuals[residuals.size() / 2]);
    subset.clear();
    double areaMm2 = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (sign * along[i] < regionFrom) continue;
      const glm::dvec3 d = points[i] - fit.centre;
      const double len = glm::length(d);
      if (std::abs(len - fit.radius) < tolerance && glm::dot(normals[i], d) > cosMax * len) {
        subset.push_back(points[i]);
        areaMm2 += areas[i];
      }
    }
    SphereFit next = fitSphere(subset, fit.centre);
    if (!next.ok) break;
    next.areaMm2 = areaMm2;
    const bool settled =
        glm::length(next.centre - fit.centre) < 1e-6 && std::abs(next.radius - fit.radius) < 1e-6;
    fit = next;
    if (settled) break;
  }
  return fit;
}

glm::dvec3 principalAxis(const std::vector<glm::dvec3>& points, const glm::dvec3& mean) {
  std::array<std::array<double, 3>, 3> cov{};
  for (const glm::dvec3& q : points) {
    const glm::dvec3 d = q - mean;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov[std::size_t(i)][std::size_t(j)] += d[i] * d[j];
  }
  glm::dvec3 v(1.0, 0.7, 0.3);  // power iteration; the long axis dominates a long bone
  for (int i = 0; i < 100; ++i) {
    glm::dvec3 w(0.0);
    for (int r = 0; r < 3; ++r) {
      const std::array<double, 3>& row = cov[std::size_t(r)];
      w[r] = row[0] * v.x + row[1] * v.y + row[2] * v.z;
    }
    const double len = glm::length(w);
    if (!(len > 0.0)) break;
    v = w / len;
  }
  return v;
}

}  // namespace

HumeralHead fitHumeralHead(const geometry::TriangleMesh& mesh, bool rightSide, HeadEnd headEnd,
                           const std::optional<glm::dvec3>& up) {
  // Triangle centroids with their face normals, each triangle split into four first so a
  // low-poly head (a few dozen facets) still gives enough points.
  std::vector<glm::dvec3> points, normals;
  std::vector<double> areas;  // of the quarter triangle each point stands for
  geometry::forEachTriangle(
      mesh, [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        const glm::dvec3 n = glm::cross(b - a, c - a);
        const double len = glm::length(n);
        if (!(len > 0.0)) return;
        const glm::dvec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
        for (const glm::dvec3 centroid : {(a + ab + ca) / 3.0, (ab + b + bc) / 3.0,
                                          (ca + bc + c) / 3.0, (ab + bc + ca) / 3.0}) {
          points.push_back(centroid);
          normals.push_back(n / len);
          areas.push_back(0.125 * len);
        }
      });
  if (points.size() < 50) throw InputError("humeral head fit: the mesh has too few points");
  glm::dvec3 mean(0.0);
  for (const glm::dvec3& p : points) mean += p;
  mean /= double(points.size());
  // Given an up axis, the head is at its end: the other end is not fitted.
  const glm::dvec3 axis = up ? glm::normalize(*up) : principalAxis(points, mean);
  std::vector<double> along(points.size());
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < points.size(); ++i) {
    along[i] = glm::dot(points[i] - mean, axis);
    lo = std::min(lo, along[i]);
    hi = std::max(hi, along[i]);
  }
  const double length = hi - lo;
  const SphereFit top =
      robustEndFit(points, normals, areas, along, hi - 0.10 * length, hi - 0.30 * length, 1.0);
  const SphereFit bottom = up ? SphereFit{}
                              : robustEndFit(points, normals, areas, along, -(lo + 0.10 * length),
                                             -(lo + 0.30 * length), -1.0);
  const auto score = [&](const SphereFit& f) {
    if (!(f.ok && f.used >= 20 && f.radius > 0.03 * length)) return 1e300;
    if (headEnd == HeadEnd::LargestCap) return f.areaMm2 > 0.0 ? 1.0 / f.areaMm2 : 1e300;
    return f.rms / f.radius;
  };
  const bool topIsHead = score(top) <= score(bottom);
  const SphereFit& head = topIsHead ? top : bottom;
  if (score(head) >= 1e300) throw InputError("humeral head fit: no end of the bone fits a sphere");

  HumeralHead out;
  out.centreMm = head.centre;
  out.radiusMm = head.radius;
  out.rmsResidualMm = head.rms;
  out.pointsUsed = head.used;
  out.capAreaMm2 = head.areaMm2;
  out.boneLengthMm = length;
  const double centreAlong = glm::dot(head.centre - mean, axis);
  out.endGapMm = topIsHead ? hi - (centreAlong + head.radius) : (centreAlong - head.radius) - lo;
  // The articular surface is the part of the bone on the sphere: its middle gives the axis.
  const glm::dvec3 toCap = head.pointsMean - head.centre;
  out.axis = glm::length(toCap) > 1e-9 ? glm::normalize(toCap) : glm::dvec3(0.0);
  out.superior = topIsHead ? axis : -axis;
  // The shaft's centre line passes through the centroid of the middle of the bone; the head
  // sits medial of it.
  glm::dvec3 shaftPoint(0.0);
  int shaftCount = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (along[i] > lo + 0.4 * length && along[i] < lo + 0.6 * length) {
      shaftPoint += points[i];
      ++shaftCount;
    }
  }
  shaftPoint = shaftCount > 0 ? shaftPoint / double(shaftCount) : mean;
  glm::dvec3 medial = head.centre - shaftPoint;
  medial -= glm::dot(medial, out.superior) * out.superior;
  if (glm::length(medial) < 1e-3 * length) {
    throw InputError("humeral head fit: the head sits on the shaft axis, so medial is undefined");
  }
  out.medial = glm::normalize(medial);
  out.anterior = glm::cross(out.medial, out.superior) * (rightSide ? 1.0 : -1.0);
  return out;
}

Portal parsePortal(const std::string& text) {
  if (text == "portal-5") return Portal::FiveOClock;
  if (text == "portal-7") return Portal::SevenOClock;
  throw OptionError("path", text, "not a portal (portal-5, portal-7) nor a .csv file");
}

namespace {

// The last crossing of the mesh along the ray (Moller-Trumbore over every triangle; run once
// per path). False when the ray meets nothing.
bool lastCrossing(const geometry::TriangleMesh& mesh, const glm::dvec3& origin,
                  const glm::dvec3& dir, glm::dvec3& pointMm, glm::dvec3& normal) {
  double best = -1.0;
  geometry::forEachTriangle(mesh,
                            [&](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                              const glm::dvec3 e1 = b - a, e2 = c - a;
                              const glm::dvec3 p = glm::cross(dir, e2);
                              const double det = glm::dot(e1, p);
                              if (std::abs(det) < 1e-14) return;
                              const glm::dvec3 s = origin - a;
                              const double u = glm::dot(s, p) / det;
                              if (u < 0.0 || u > 1.0) return;
                              const glm::dvec3 q = glm::cross(s, e1);
                              const double v = glm::dot(dir, q) / det;
                              if (v < 0.0 || u + v > 1.0) return;
                              const double dist = glm::dot(e2, q) / det;
                              if (dist > best) {
                                best = dist;
                                pointMm = origin + dist * dir;
                                normal = glm::normalize(glm::cross(e1, e2));
                              }
                            });
  return best > 0.0;
}

}  // namespace

PortalPlan makePortalPath(Portal portal, const HumeralHead& head,
                          const geometry::TriangleMesh& mesh, double toolOuterRadiusMm,
                          const PortalPathOptions& options) {
  // Clock angle from 12 (superior) towards 3 (anterior): 5 o'clock is 150 degrees. The clock
  // face lies on the articular surface, a cone of half-angle options.clockConeDeg around the
  // head axis, so every hour is on the head itself.
  const double theta = (portal == Portal::FiveOClock ? 150.0 : 210.0) * M_PI / 180.0;
  glm::dvec3 h = head.axis;
  if (!(glm::length(h) > 0.5)) h = head.medial;  // no cap found: face medially
  glm::dvec3 up = head.superior - glm::dot(head.superior, h) * h;
  if (glm::length(up) < 1e-6) up = head.anterior - glm::dot(head.anterior, h) * h;
  up = glm::normalize(up);
  glm::dvec3 front = glm::cross(h, up);
  if (glm::dot(front, head.anterior) < 0.0) front = -front;
  const double cone = options.clockConeDeg * M_PI / 180.0;
  PortalPlan plan;
  plan.clockDirection = glm::normalize(
      std::cos(cone) * h + std::sin(cone) * (std::cos(theta) * up + std::sin(theta) * front));
  if (!lastCrossing(mesh, head.centreMm, plan.clockDirection, plan.entryMm, plan.normal)) {
    throw InputError(std::string(portal == Portal::FiveOClock ? "portal-5" : "portal-7") +
                     ": the ray from the head centre towards the portal never leaves the bone");
  }
  if (glm::dot(plan.normal, plan.clockDirection) < 0.0) plan.normal = -plan.normal;
  // Tilted from the inward normal towards the articular pole, so the path stays in the head.
  glm::dvec3 tangent = h - glm::dot(h, plan.normal) * plan.normal;
  if (glm::length(tangent) < 1e-6) tangent = up - glm::dot(up, plan.normal) * plan.normal;
  tangent = glm::normalize(tangent);
  const double a = options.entryAngleDeg * M_PI / 180.0;
  plan.direction = glm::normalize(-std::cos(a) * plan.normal + std::sin(a) * tangent);
  // Back from the entry until the cushion clears the tangent plane by the clearance.
  const double approachMm = (toolOuterRadiusMm + options.clearanceMm) / std::cos(a);
  const glm::dvec3 start = plan.entryMm - approachMm * plan.direction;
  const glm::dvec3 end = plan.entryMm + options.depthMm * plan.direction;
  plan.speedMmPerS = (approachMm + options.depthMm) / options.durationS;
  glm::dquat q = ToolPose::pointing(start, plan.direction).orientation;
  if (options.tiltDeg != 0.0) {
    // About the tip (the tool frame's origin): the forward direction turns towards -normal.
    const glm::dvec3 axis = glm::normalize(glm::cross(plan.normal, plan.direction));
    q = glm::normalize(glm::angleAxis(options.tiltDeg * M_PI / 180.0, axis) * q);
  }
  plan.path = DrillPath({Waypoint{0.0, start, q, true}, Waypoint{options.durationS, end, q, true}});
  return plan;
}

DrillPath::DrillPath(std::vector<Waypoint> points) : points_(std::move(points)) {}

void DrillPath::sample(double tS, ToolPose& pose, bool& drillOn) const {
  if (points_.empty()) {
    pose = ToolPose{};
    drillOn = false;
    return;
  }
  if (tS <= points_.front().tS || points_.size() == 1) {
    pose = ToolPose{points_.front().tipMm, points_.front().orientation};
    drillOn = points_.front().drillOn;
    return;
  }
  if (tS >= points_.back().tS) {
    pose = ToolPose{points_.back().tipMm, points_.back().orientation};
    drillOn = points_.back().drillOn;
    return;
  }
  if (cursor_ + 1 >= points_.size() || points_[cursor_].tS > tS) cursor_ = 0;
  while (points_[cursor_ + 1].tS < tS) ++cursor_;
  const Waypoint& a = points_[cursor_];
  const Waypoint& b = points_[cursor_ + 1];
  const double s = (tS - a.tS) / (b.tS - a.tS);
  pose.tipMm = a.tipMm + s * (b.tipMm - a.tipMm);
  glm::dquat qb = b.orientation;
  if (glm::dot(a.orientation, qb) < 0.0) qb = -qb;
  pose.orientation = glm::normalize(a.orientation * (1.0 - s) + qb * s);
  drillOn = a.drillOn;
}

namespace {

// False for the zero quaternion. Far from 1 the components are divided by the largest first,
// so the sum of squares neither overflows nor underflows; near 1 the plain sum is kept (the
// same bits as before for ordinary paths).
bool unitQuaternion(const glm::dquat& q, glm::dquat& unit) {
  const double largest = std::max({std::abs(q.w), std::abs(q.x), std::abs(q.y), std::abs(q.z)});
  if (!(largest > 0.0)) return false;
  if (largest >= 1e-100 && largest <= 1e100) {
    unit = glm::normalize(q);
  } else {
    unit = glm::normalize(glm::dquat(q.w / largest, q.x / largest, q.y / largest, q.z / largest));
  }
  return true;
}

}  // namespace

bool isPathCsv(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".csv";
}

DrillPath loadPathCsv(const std::string& path) {
  requireRegularFile(path, "the path file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the path file");
  std::string line;
  if (!std::getline(in, line))
    throw InputError(path + ": empty path file (expected a header row t,x,y,z,drill_on)");
  if (line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // a UTF-8 byte order mark
  const auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::stringstream s(text);
    std::string cell;
    while (std::getline(s, cell, ',')) {
      cell.erase(0, cell.find_first_not_of(" \t\r"));
      cell.erase(cell.find_last_not_of(" \t\r") + 1);
      cells.push_back(cell);
    }
    return cells;
  };
  const std::vector<std::string> header = split(line);
  const bool withQuat = header.size() == 9;
  if ((header.size() != 5 && !withQuat) || header[0] != "t" || header[1] != "x" ||
      header[2] != "y" || header[3] != "z" || header[4] != "drill_on") {
    throw InputError(path + ":1: header must be t,x,y,z,drill_on (optionally ,qw,qx,qy,qz)");
  }
  std::vector<Waypoint> points;
  std::vector<bool> hasOrientation;
  for (int lineNo = 2; std::getline(in, line); ++lineNo) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = split(line);
    const std::string where = path + ":" + std::to_string(lineNo) + ": ";
    if (cells.size() != header.size()) {
      throw InputError(where + "expected " + std::to_string(header.size()) + " values, found " +
                       std::to_string(cells.size()));
    }
    std::array<double, 9> v{};
    for (std::size_t i = 0; i < cells.size(); ++i) {
      std::size_t used = 0;
      try {
        v[i] = std::stod(cells[i], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != cells[i].size() || cells[i].empty() || !std::isfinite(v[i])) {
        throw InputError(where + "'" + cells[i] + "' in column " + header[i] +
                         " is not a finite number");
      }
    }
    for (std::size_t i = 1; i < 4; ++i) {
      if (std::abs(v[i]) > kMaxPathCoordinateMm) {
        throw InputError(where + "'" + cells[i] + "' in column " + header[i] +
                         " is beyond +-1e9 mm (1000 km)");
      }
    }
    if (v[4] != 0.0 && v[4] != 1.0) throw InputError(where + "drill_on must be 0 or 1");
    if (!points.empty() && !(v[0] > points.back().tS))
      throw InputError(where + "times must increase");
    if (v[0] < 0.0) throw InputError(where + "time must not be negative");
    if (v[0] > kMaxPathDurationS) {
      char limit[32];
      std::snprintf(limit, sizeof limit, "%g", kMaxPathDurationS);
      throw InputError(where + "t = " + cells[0] + " s is past the longest path allowed (" + limit +
                       " s)");
    }
    Waypoint w;
    w.tS = v[0];
    w.tipMm = {v[1], v[2], v[3]};
    w.drillOn = v[4] == 1.0;
    if (withQuat) {
      if (!unitQuaternion(glm::dquat(v[5], v[6], v[7], v[8]), w.orientation)) {
        throw InputError(where + "the orientation quaternion is zero");
      }
    }
    points.push_back(w);
  }
  if (points.size() < 2) throw InputError(path + ": a path needs at least two rows");
  if (!withQuat) {
    // The tool points along its travel; where it stands still it keeps its last direction.
    glm::dvec3 last(0.0, 0.0, -1.0);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const glm::dvec3 d =
          i + 1 < points.size() ? points[i + 1].tipMm - points[i].tipMm : glm::dvec3(0.0);
      if (glm::length(d) > 1e-9) last = d;
      points[i].orientation = ToolPose::pointing(points[i].tipMm, last).orientation;
    }
  }
  return DrillPath(std::move(points));
}

}  // namespace osteon::simulation
