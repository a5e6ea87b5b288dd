#include "osteon/simulation/coupling.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "osteon/core/checks.h"
#include "osteon/core/error.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

CouplingMode parseCouplingMode(const std::string& text) {
  if (text == "proxy") return CouplingMode::Proxy;
  if (text == "direct") return CouplingMode::Direct;
  throw OptionError("coupling", text, "unknown coupling (use proxy or direct)");
}

const char* couplingModeName(CouplingMode mode) {
  return mode == CouplingMode::Proxy ? "proxy" : "direct";
}

void validateCouplingOptions(const CouplingOptions& o) {
  requirePositive(o.stiffnessNPerMm, "coupling stiffness (N/mm)");
  requirePositive(o.virtualMassKg, "coupling virtual mass (kg)");
  requirePositive(o.rotationalStiffnessNmmPerRad, "coupling rotational stiffness (N mm/rad)");
  requirePositive(o.contactSlewNPerS, "coupling contact slew (N/s)");
  requirePositive(o.rotationalInertiaKgMm2, "coupling rotational inertia (kg mm^2)");
  requirePositive(o.rateFilterS, "coupling rate filter (s)");
  requirePositive(o.cutRampS, "coupling cut ramp (s)");
  requirePositive(o.anchorSpeedMmPerS, "coupling anchor speed (mm/s)");
  requirePositive(o.maxFeedMmPerS, "coupling feed limit (mm/s)");
  if (!(o.frictionCoefficient >= 0.0) || !std::isfinite(o.frictionCoefficient)) {
    throw InputError("coupling friction coefficient: must be a finite number >= 0");
  }
  if (!std::isfinite(o.dampingNsPerMm) || !std::isfinite(o.rotationalDampingNmmSPerRad)) {
    throw InputError("coupling damping: must be a finite number (< 0: critically damped)");
  }
  if (o.candidateCapacity == 0) throw InputError("coupling candidate capacity: must be at least 1");
}

namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The rotation vector (axis times angle, rad) taking `to` to `from`: from * conj(to).
glm::dvec3 rotationVector(const glm::dquat& from, const glm::dquat& to) {
  glm::dquat q = from * glm::conjugate(to);
  if (q.w < 0.0) q = -q;
  const glm::dvec3 v(q.x, q.y, q.z);
  const double s = glm::length(v);
  if (!(s > 1e-15)) return 2.0 * v;  // small angles: the vector part is half the rotation vector
  return (2.0 * std::atan2(s, q.w) / s) * v;
}

}  // namespace

ProxyCoupling::ProxyCoupling(DrillingSimulation& sim, const CouplingOptions& options)
    : sim_(&sim), options_(options) {
  validateCouplingOptions(options);
  const double k = options.stiffnessNPerMm * 1e3;  // N/m
  dampingNsPerMm_ = options.dampingNsPerMm >= 0.0
                        ? options.dampingNsPerMm
                        : 2.0 * std::sqrt(k * options.virtualMassKg) * 1e-3;
  // N mm/rad and kg mm^2: 2 sqrt(kr I) in N m s/rad is 2 sqrt(kr[N mm] I[kg mm^2] 1e-9) 1e3 N mm s.
  rotationalDamping_ = options.rotationalDampingNmmSPerRad >= 0.0
                           ? options.rotationalDampingNmmSPerRad
                           : 2.0 *
                                 std::sqrt(options.rotationalStiffnessNmmPerRad *
                                           options.rotationalInertiaKgMm2 * 1e-9) *
                                 1e3;
  const Tool& tool = sim.tool();
  double thinnest = 1e300;
  reachMm_ = 0.0;
  cushionMm_ = 0.0;
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    thinnest = std::min(thinnest, part.innerRadiusMm);
    reachMm_ = std::max(
        reachMm_, std::max(glm::length(part.aMm), glm::length(part.bMm)) + part.outerRadiusMm);
    // The cut's lead: a cushion, but no more than half the inner radius (a static coarse grid's
    // cushion of two 1.2 mm voxels would cut a sphere barely touching the proxy's).
    if (part.cuts) {
      cutterRadiusMm_ = std::max(cutterRadiusMm_, part.innerRadiusMm);
      cushionMm_ = std::max(
          cushionMm_, std::min(part.outerRadiusMm - part.innerRadiusMm, 0.5 * part.innerRadiusMm));
    }
    candidates_[std::size_t(p)].samples.reserve(options.candidateCapacity);
    admitRadiusMm_[std::size_t(p)] = part.innerRadiusMm;
  }
  subMoveMm_ = 0.5 * thinnest;
}

void ProxyCoupling::reset(const ToolPose& pose) {
  proxy_ = pose;
  started_ = true;
  cutAdvanceMm_ = 0.0;
  lastForceN_ = glm::dvec3(0.0);
  anchorMm_ = pose.tipMm;
  contactForceN_ = glm::dvec3(0.0);
  lastGapMm_ = gapRate_ = glm::dvec3(0.0);
  lastTwistRad_ = twistRate_ = glm::dvec3(0.0);
}

// The layers the proxy is held out of: a cutting part's narrowed while its cut runs ahead.
void ProxyCoupling::admitLayers(bool drillOn) {
  const Tool& tool = sim_->tool();
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    const double ahead =
        part.cuts && drillOn ? std::min(cutAdvanceMm_, 0.5 * part.innerRadiusMm) : 0.0;
    admitRadiusMm_[std::size_t(p)] =
        std::sqrt(part.innerRadiusMm * part.innerRadiusMm - ahead * ahead);
  }
}

HapticStep ProxyCoupling::step(const StepInput& commanded) {
  HapticStep h;
  h.commanded = commanded.pose;
  const glm::dvec3& cmdTip = commanded.pose.tipMm;
  const glm::dquat& q = commanded.pose.orientation;
  if (!std::isfinite(cmdTip.x + cmdTip.y + cmdTip.z + q.w + q.x + q.y + q.z + commanded.tS)) {
    // A broken command: the simulation counts it and gives no force; the proxy stays.
    h.step = sim_->step(commanded);
    h.proxy = h.stepPose = proxy_;
    ++totals_.steps;
    return h;
  }
  double dtS = 0.001;
  if (!started_) {
    reset(commanded.pose);
  } else if (commanded.tS - lastS_ > 0.0 && commanded.tS - lastS_ < 0.1) {
    dtS = commanded.tS - lastS_;
  }
  lastS_ = commanded.tS;

  admitLayers(commanded.drillOn);
  feedLimitMmPerS_ = options_.maxFeedMmPerS;
  feedBoneAhead_ = false;
  if (options_.forceModel == ForceModelKind::Calibrated && commanded.drillOn)
    calibratedFeed(commanded, h);
  // The proxy: as far toward the command as the bone lets it, then along the contact plane.
  moveProxy(commanded, dtS);
  h.proxy = proxy_;

  // Where the step runs: the drill on, up to a cushion ahead of the proxy toward the command.
  const double target = commanded.drillOn ? cushionMm_ : 0.0;
  const double rampMm = cushionMm_ * dtS / options_.cutRampS;
  cutAdvanceMm_ = cutAdvanceMm_ < target ? std::min(target, cutAdvanceMm_ + rampMm)
                                         : std::max(target, cutAdvanceMm_ - rampMm);
  h.stepPose = proxy_;
  const glm::dvec3 ahead = cmdTip - proxy_.tipMm;
  const double aheadMm = glm::length(ahead);
  if (cutAdvanceMm_ > 0.0 && aheadMm > 0.0)
    h.stepPose.tipMm += (std::min(cutAdvanceMm_, aheadMm) / aheadMm) * ahead;
  h.step = sim_->step({commanded.tS, h.stepPose, commanded.drillOn, commanded.settings});

  // The spring's anchor follows the proxy at most anchorSpeedMmPerS, also as the proxy catches
  // up with the command: were the anchor set onto it then, the spring's force would drop in one
  // step (a hand's tremor out of a cut felt as 0.4 N knocks).
  const glm::dvec3 lag = proxy_.tipMm - anchorMm_;
  const double lagMm = glm::length(lag), stepMm = options_.anchorSpeedMmPerS * dtS;
  anchorMm_ = !(lagMm > stepMm) ? proxy_.tipMm : anchorMm_ + (stepMm / lagMm) * lag;
  // The coupling: spring-damper on the gap, the damping on a low-passed gap rate.
  const glm::dvec3 gap = anchorMm_ - cmdTip;
  const glm::dvec3 twist = rotationVector(proxy_.orientation, commanded.pose.orientation);
  const double alpha = dtS / (options_.rateFilterS + dtS);
  if (totals_.steps > 0) {
    gapRate_ += alpha * ((gap - lastGapMm_) / dtS - gapRate_);
    twistRate_ += alpha * ((twist - lastTwistRad_) / dtS - twistRate_);
  }
  lastGapMm_ = gap;
  lastTwistRad_ = twist;
  h.gapMm = glm::length(proxy_.tipMm - cmdTip);
  // As the force: toward the proxy, about the rotation that takes the command to it.
  h.torqueNmm = options_.rotationalStiffnessNmmPerRad * twist + rotationalDamping_ * twistRate_;
  // The device is pulled toward the proxy: k (anchor - command) + b d/dt (anchor - command).
  // The contact force (seed eqs. 1-2) at the proxy, slew-limited: drawn back through its own
  // hole the proxy's shell holds bone all round, and eq. (1)'s direction turns over within a
  // sample's travel; the hand feels the turn as a slope, not a step.
  if (totals_.steps == 0) {
    contactForceN_ = h.step.contact.forceN;
  } else if (finite(h.step.contact.forceN)) {
    const glm::dvec3 change = h.step.contact.forceN - contactForceN_;
    const double changeN = glm::length(change), slewN = options_.contactSlewNPerS * dtS;
    contactForceN_ += changeN > slewN ? (slewN / changeN) * change : change;
  }
  glm::dvec3 force = options_.stiffnessNPerMm * gap + dampingNsPerMm_ * gapRate_ + contactForceN_;
  double magnitude = glm::length(force);
  if (!finite(force) || !std::isfinite(magnitude) || !finite(h.torqueNmm)) {
    ++totals_.nonFiniteForces;
    force = glm::dvec3(0.0);
    magnitude = 0.0;
    h.torqueNmm = glm::dvec3(0.0);
    gapRate_ = twistRate_ = glm::dvec3(0.0);
  }
  const double maxN = sim_->tool().maxForceN;
  if (magnitude >= maxN) {
    force *= maxN / magnitude;
    magnitude = maxN;
    h.clamped = true;
  }
  h.forceN = force;
  h.magnitudeN = magnitude;
  lastForceN_ = force;
  if (options_.thermal) depositHeat(commanded, h, dtS);

  ++totals_.steps;
  totals_.clampSteps += h.clamped ? 1 : 0;
  totals_.maxGapMm = std::max(totals_.maxGapMm, h.gapMm);
  return h;
}

// The bone ahead of the tip (the cutting sphere's front, on the tool's axis), trilinear over the
// material grid's voxels weighted by their fill: its apparent density, 0 where there is none.
static double densityAheadGcm3(const geometry::VoxelGrid& grid, const glm::dvec3& pMm) {
  const glm::dvec3 g = grid.gridFromWorld(pMm) - 0.5;
  const glm::dvec3 base(std::floor(g.x), std::floor(g.y), std::floor(g.z));
  const glm::dvec3 f = g - base;
  const glm::ivec3 i0(base);
  double weight = 0.0, rho = 0.0;
  for (int c = 0; c < 8; ++c) {
    const glm::ivec3 o((c & 1) != 0, (c & 2) != 0, (c & 4) != 0);
    const double w = (o.x ? f.x : 1.0 - f.x) * (o.y ? f.y : 1.0 - f.y) * (o.z ? f.z : 1.0 - f.z) *
                     double(grid.fill(i0 + o)) / double(geometry::kFillFull);
    if (!(w > 0.0)) continue;
    weight += w;
    rho += w * apparentDensityGcm3(double(grid.density(i0 + o)));
  }
  return weight > 1e-6 ? rho / weight : 0.0;
}

void ProxyCoupling::calibratedFeed(const StepInput& commanded, HapticStep& h) {
  if (!options_.materialGrid) return;
  const glm::dvec3 front = proxy_.tipMm + cutterRadiusMm_ * proxy_.forward();
  h.densityGcm3 = densityAheadGcm3(*options_.materialGrid, front);
  // The hand's push along the tool: the force sent points back against it.
  const double pushN = std::max(0.0, -glm::dot(lastForceN_, proxy_.forward()));
  h.thrustRealN = pushN / kDeviceNPerRealN;
  feedBoneAhead_ = h.densityGcm3 > 0.0;
  if (feedBoneAhead_) {
    const double lawMmPerS = options_.thrust.feedMmPerS(
        h.thrustRealN, h.densityGcm3, 2.0 * cutterRadiusMm_, commanded.settings.rpm);
    feedLimitMmPerS_ = std::min(feedLimitMmPerS_, lawMmPerS);
  }
  h.feedLimitMmPerS = feedLimitMmPerS_;
}

void ProxyCoupling::depositHeat(const StepInput& commanded, HapticStep& h, double dtS) {
  const double vs = sim_->grid().voxelSizeMm();
  HeatInput in;
  in.tipMm = h.stepPose.tipMm;
  in.removedMm3 = h.step.removal.removedVolumeMm3(vs * vs * vs);
  in.rhoGcm3 = h.densityGcm3;
  in.rpm = commanded.settings.rpm;
  in.diameterMm = 2.0 * cutterRadiusMm_;
  in.thrustN = h.thrustRealN;
  in.irrigation = commanded.settings.irrigation;
  in.cutting = commanded.drillOn && h.densityGcm3 > 0.0;
  in.dtS = dtS;
  options_.thermal->deposit(in);
  h.temperatureC = options_.thermal->tipTemperatureC();
}

HapticStep stepHaptic(DrillingSimulation& sim, ProxyCoupling* coupling,
                      const StepInput& commanded) {
  if (coupling) return coupling->step(commanded);
  HapticStep h;
  h.step = sim.step(commanded);
  h.commanded = h.proxy = h.stepPose = commanded.pose;
  h.forceN = h.step.contact.forceN;
  h.magnitudeN = h.step.contact.magnitudeN;
  h.clamped = h.magnitudeN >= sim.tool().maxForceN;
  return h;
}

}  // namespace osteon::simulation
