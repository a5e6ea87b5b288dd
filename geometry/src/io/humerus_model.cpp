#include "osteon/geometry/io/humerus_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "osteon/core/checks.h"
#include "osteon/core/error.h"
#include "surface/marching_tetrahedra.h"

namespace osteon::geometry {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kMetaphysisDepthRatio = 0.8;  // front-to-back over side-to-side width
constexpr double kNeckRecess = 0.12;           // neck below the articular sphere, in radii

// Polynomial smooth minimum: a union whose crease is rounded over about k millimetres.
double smoothMin(double a, double b, double kMm) {
  const double h = std::max(kMm - std::abs(a - b), 0.0) / kMm;
  return std::min(a, b) - 0.25 * kMm * h * h;
}

// 0 below edge0, 1 above edge1, a cubic between.
double smoothStep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

double smoothMax(double a, double b, double kMm) {
  return -smoothMin(-a, -b, kMm);
}

// Ellipsoid distance bound k0 (k0 - 1) / k1: exact on the surface, a good distance
// estimate near it and smooth everywhere but the centre.
double ellipsoid(const glm::dvec3& pMm, const glm::dvec3& centreMm, const glm::dvec3& radiiMm) {
  const glm::dvec3 d = pMm - centreMm;
  const double k0 = glm::length(d / radiiMm);
  const double k1 = glm::length(d / (radiiMm * radiiMm));
  if (k1 == 0.0) return -std::min(radiiMm.x, std::min(radiiMm.y, radiiMm.z));
  return k0 * (k0 - 1.0) / k1;
}

// Flat-ended cylinder from a to b, its rim rounded by roundMm.
double roundedCylinder(const glm::dvec3& pMm, const glm::dvec3& aMm, const glm::dvec3& bMm,
                       double radiusMm, double roundMm) {
  const double lengthMm = glm::length(bMm - aMm);
  const glm::dvec3 axis = (bMm - aMm) / lengthMm;
  const double along = glm::dot(pMm - aMm, axis);
  const double dr = glm::length(pMm - aMm - along * axis) - radiusMm + roundMm;
  const double dz = std::abs(along - 0.5 * lengthMm) - (0.5 * lengthMm - roundMm);
  return std::min(std::max(dr, dz), 0.0) + std::hypot(std::max(dr, 0.0), std::max(dz, 0.0)) -
         roundMm;
}

// Convex hull of a ball of radius lowRadiusMm at a and one of highRadiusMm at b: a cone with
// rounded ends.
double roundCone(const glm::dvec3& pMm, const glm::dvec3& aMm, double lowRadiusMm,
                 const glm::dvec3& bMm, double highRadiusMm) {
  const glm::dvec3 ab = bMm - aMm;
  const double lengthMm = glm::length(ab);
  const glm::dvec3 axis = ab / lengthMm;
  const glm::dvec3 q = pMm - aMm;
  const double along = glm::dot(q, axis);
  const double across = glm::length(q - along * axis);
  // (cosine, sine) of the cone's half-angle
  const double sine = (lowRadiusMm - highRadiusMm) / lengthMm;
  const double cosine = std::sqrt(std::max(1.0 - sine * sine, 0.0));
  const double side = -sine * across + cosine * along;  // where the tangent lines touch
  if (side < 0.0) return std::hypot(across, along) - lowRadiusMm;
  if (side > cosine * lengthMm) return std::hypot(across, along - lengthMm) - highRadiusMm;
  return cosine * across + sine * along - lowRadiusMm;
}

// Segment a-b swept by a ball of radius radiusMm.
double capsule(const glm::dvec3& pMm, const glm::dvec3& aMm, const glm::dvec3& bMm,
               double radiusMm) {
  const glm::dvec3 ab = bMm - aMm;
  const double t = std::clamp(glm::dot(pMm - aMm, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(pMm - aMm - t * ab) - radiusMm;
}

// The bone as a smooth union of primitives, all placed from the parameters. Head sizes
// scale with the head radius, shaft-related ones with the shaft radius.
struct Humerus {
  explicit Humerus(const HumerusModelParams& params) {
    headRadiusMm = 0.5 * params.headDiameterMm;
    shaftRadiusMm = 0.5 * params.shaftDiameterMm;
    shaftLengthMm = params.shaftLengthMm;
    const double r = headRadiusMm;
    const double retro = params.retroversionDeg * kDegToRad;
    const double elevation = (params.neckShaftAngleDeg - 90.0) * kDegToRad;
    const glm::dvec3 medial(std::cos(retro), std::sin(retro), 0.0);
    headAxis = std::cos(elevation) * medial + std::sin(elevation) * glm::dvec3(0.0, 0.0, 1.0);
    // Head centre: offset medially (and with the retroversion, posteriorly) from the shaft
    // axis, about one head radius above the surgical neck at z = 0.
    headCentreMm = 0.5 * shaftRadiusMm * medial + glm::dvec3(0.0, 0.0, 1.15 * r);
    // The articular cap spans about 152 degrees of arc: the neck plane is 0.24 R in front
    // of the centre.
    capPlaneMm = 0.24 * r;
    // The anatomical neck: a cone narrowing from a ball concentric with the head, slightly
    // smaller so the cap's margin stands proud of it, down and laterally into the
    // metaphysis. Its underside is the calcar.
    neckHeadRadiusMm = (1.0 - kNeckRecess) * r;
    neckBaseMm = headCentreMm - 0.8 * r * headAxis;
    neckBaseRadiusMm = 0.6 * r;

    metaphysisLowMm = glm::dvec3(0.0, 0.0, -0.2 * r);
    metaphysisLowRadiusMm = shaftRadiusMm;
    metaphysisHighMm = glm::dvec3(-0.15 * r, 0.05 * r, 1.1 * r);
    metaphysisHighRadiusMm = 0.8 * r;
    greaterCentreMm = glm::dvec3(-0.55 * r, 0.0 * r, 1.36 * r);
    greaterRadiiMm = glm::dvec3(0.45 * r, 0.65 * r, 0.55 * r);
    lesserCentreMm = glm::dvec3(0.05 * r, -0.58 * r, 1.1 * r);
    lesserRadiiMm = glm::dvec3(0.28 * r, 0.32 * r, 0.42 * r);
    // The groove fades out on the shaft, so its lower end follows the shaft's surface.
    grooveRadiusMm = 0.25 * r;
    const double grooveLowOffsetMm = shaftRadiusMm + grooveRadiusMm - 0.035 * r;
    grooveLowMm = glm::dvec3(-0.33 * grooveLowOffsetMm, -0.944 * grooveLowOffsetMm, -0.3 * r);
    grooveHighMm = glm::dvec3(-0.3 * r, -0.826 * r, 1.9 * r);
    shaftTopMm = 1.0 * r;
  }

  double operator()(const glm::dvec3& p) const {
    const double r = headRadiusMm;
    const double shaft =
        roundedCylinder(p, glm::dvec3(0.0, 0.0, -shaftLengthMm), glm::dvec3(0.0, 0.0, shaftTopMm),
                        shaftRadiusMm, 0.3 * shaftRadiusMm);
    // The metaphysis is flatter front to back than side to side: a round cone squeezed in
    // y. Scaling the distance by the mean squeeze keeps it close to a distance.
    const glm::dvec3 squeezed(p.x, p.y / kMetaphysisDepthRatio, p.z);
    const double metaphysis = 0.5 * (1.0 + kMetaphysisDepthRatio) *
                              roundCone(squeezed, metaphysisLowMm, metaphysisLowRadiusMm,
                                        metaphysisHighMm, metaphysisHighRadiusMm);
    const double sphere = glm::length(p - headCentreMm) - r;
    const double cap =
        smoothMax(sphere, capPlaneMm - glm::dot(p - headCentreMm, headAxis), 0.15 * r);
    const double neck = roundCone(p, neckBaseMm, neckBaseRadiusMm, headCentreMm, neckHeadRadiusMm);
    const double greater = ellipsoid(p, greaterCentreMm, greaterRadiiMm);
    const double lesser = ellipsoid(p, lesserCentreMm, lesserRadiiMm);

    double d = smoothMin(shaft, metaphysis, 0.6 * shaftRadiusMm);
    d = smoothMin(d, neck, 0.25 * r);
    d = smoothMin(d, greater, 0.3 * r);
    d = smoothMin(d, lesser, 0.2 * r);
    // Within 60 degrees of the head axis the blend is narrower than the neck's recess, which
    // leaves the cap exactly on the sphere; it widens towards the margin so the anatomical
    // neck is a soft groove rather than a step.
    const glm::dvec3 fromCentre = p - headCentreMm;
    const double cosine = glm::dot(fromCentre, headAxis) / std::max(glm::length(fromCentre), 1e-9);
    const double capBlendMm = r * (0.3 + (0.8 * kNeckRecess - 0.3) * smoothStep(0.3, 0.5, cosine));
    d = smoothMin(d, cap, capBlendMm);
    // The bicipital groove between the tuberosities, carved with rounded lips.
    return smoothMax(d, -capsule(p, grooveLowMm, grooveHighMm, grooveRadiusMm), 0.15 * r);
  }

  Aabb bounds() const {
    const double r = headRadiusMm;
    Aabb box;
    const double side = std::max(2.0 * r, 1.5 * shaftRadiusMm);
    // The metaphysis cone and the neck reach below z = 0 even when the shaft is short.
    const double bottomMm = std::min(-shaftLengthMm, -0.3 * r - shaftRadiusMm);
    box.minMm = glm::dvec3(-side, -side, bottomMm - 1.0);
    box.maxMm = glm::dvec3(side, side, headCentreMm.z + r + 1.0);
    return box;
  }

  double headRadiusMm = 0.0;
  double shaftRadiusMm = 0.0;
  double shaftLengthMm = 0.0;
  glm::dvec3 headAxis{0.0};
  glm::dvec3 headCentreMm{0.0};
  double capPlaneMm = 0.0;
  double neckHeadRadiusMm = 0.0;
  glm::dvec3 neckBaseMm{0.0};
  double neckBaseRadiusMm = 0.0;
  glm::dvec3 metaphysisLowMm{0.0};
  double metaphysisLowRadiusMm = 0.0;
  glm::dvec3 metaphysisHighMm{0.0};
  double metaphysisHighRadiusMm = 0.0;
  glm::dvec3 greaterCentreMm{0.0};
  glm::dvec3 greaterRadiiMm{0.0};
  glm::dvec3 lesserCentreMm{0.0};
  glm::dvec3 lesserRadiiMm{0.0};
  glm::dvec3 grooveLowMm{0.0};
  glm::dvec3 grooveHighMm{0.0};
  double grooveRadiusMm = 0.0;
  double shaftTopMm = 0.0;
};

void validate(const HumerusModelParams& params) {
  requirePositive(params.headDiameterMm, "headDiameterMm");
  requirePositive(params.neckShaftAngleDeg, "neckShaftAngleDeg");
  requirePositive(params.shaftDiameterMm, "shaftDiameterMm");
  requirePositive(params.shaftLengthMm, "shaftLengthMm");
  requirePositive(params.tessellationMm, "tessellationMm");
  // Turned further forward, the head's margin runs into the lesser tuberosity and groove.
  if (!std::isfinite(params.retroversionDeg) || params.retroversionDeg < -30.0 ||
      params.retroversionDeg > 80.0) {
    throw InputError("retroversionDeg: must be within [-30, 80], got " +
                     std::to_string(params.retroversionDeg));
  }
  if (params.neckShaftAngleDeg <= 90.0 || params.neckShaftAngleDeg >= 180.0) {
    throw InputError("neckShaftAngleDeg: must be within (90, 180), got " +
                     std::to_string(params.neckShaftAngleDeg));
  }
  // Coarser than this and the grid (twice the edge length) no longer resolves the bone.
  if (params.tessellationMm > 0.125 * params.shaftDiameterMm) {
    throw InputError("tessellationMm: must be at most an eighth of shaftDiameterMm, got " +
                     std::to_string(params.tessellationMm));
  }
}

}  // namespace

HumerusModel buildHumerusModel(const HumerusModelParams& params) {
  validate(params);
  const Humerus humerus(params);
  const Aabb box = humerus.bounds();
  // Kuhn tetrahedra cut each crossed cube into edges about half the grid spacing long.
  const double gridMm = 2.0 * params.tessellationMm;
  const glm::dvec3 cells = box.extentMm() / gridMm;
  // A finer grid would take gigabytes (32 bytes per grid point): refuse rather than exhaust
  // memory. The limit allows edges down to about 0.25 mm on the default bone.
  if (cells.x * cells.y * cells.z > 1.0e7) {
    throw InputError("tessellationMm: too fine for the model size, got " +
                     std::to_string(params.tessellationMm));
  }
  const detail::ImplicitFunction f = [&humerus](const glm::dvec3& p) { return humerus(p); };

  HumerusModel model;
  model.mesh = detail::marchingTetrahedra(f, box, gridMm);
  detail::relaxOntoZeroSet(model.mesh, f, gridMm, 8);
  model.headCentreMm = humerus.headCentreMm;
  model.headRadiusMm = humerus.headRadiusMm;
  model.headAxis = humerus.headAxis;
  model.shaftAxis = glm::dvec3(0.0, 0.0, 1.0);
  return model;
}

}  // namespace osteon::geometry
