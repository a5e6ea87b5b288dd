#include "osteon/simulation/coupling.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "osteon/core/checks.h"
#include "osteon/core/error.h"

namespace osteon::simulation {

CouplingMode parseCouplingMode(const std::string& text) {
  if (text == "proxy") return CouplingMode::Proxy;
  if (text == "direct") return CouplingMode::Direct;
  throw InputError("--coupling " + text + ": unknown coupling (use proxy or direct)");
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

ToolPose interpolate(const ToolPose& a, const ToolPose& b, double t) {
  if (t >= 1.0) return b;
  if (t <= 0.0) return a;
  ToolPose p;
  p.tipMm = a.tipMm + t * (b.tipMm - a.tipMm);
  p.orientation = glm::normalize(glm::slerp(a.orientation, b.orientation, t));
  return p;
}

// The angle (rad) of the shortest rotation between two orientations.
double angleBetween(const glm::dquat& a, const glm::dquat& b) {
  const double c = std::min(1.0, std::abs(glm::dot(a, b)));
  return 2.0 * std::acos(c);
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

// A part's core segment at a pose, for distances from sample centres to it.
struct CoreSegment {
  glm::dvec3 a, b, ab;
  double invLen2 = 0.0;  // 1 / |ab|^2, or 0 for a point

  CoreSegment(const ToolPose& pose, const ToolPart& part)
      : a(pose.toWorld(part.aMm)), b(pose.toWorld(part.bMm)), ab(b - a) {
    const double len2 = glm::dot(ab, ab);
    invLen2 = len2 > 0.0 ? 1.0 / len2 : 0.0;
  }
  // Squared distance from c to the segment; toCore, when given, runs from c to its nearest point.
  double distance2(const glm::dvec3& c, glm::dvec3* toCore = nullptr) const {
    const double t = std::clamp(glm::dot(c - a, ab) * invLen2, 0.0, 1.0);
    const glm::dvec3 d = a + t * ab - c;
    if (toCore) *toCore = d;
    return glm::dot(d, d);
  }
};

// fn(sample) for every bone sample whose centre may lie within rMm of the core (the hierarchy
// walk opens only voxels that reach that far).
template <typename Fn>
void forEachSampleNearCore(geometry::RefinedVoxels& voxels, const CoreSegment& core, double rMm,
                           Fn&& fn) {
  voxels.forEachSampleNearSegment(
      core.a, core.b, rMm,
      [&](const glm::dvec3& c, double h) {
        const double far = rMm + h;
        return core.distance2(c) <= far * far;
      },
      fn);
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
  anchorMm_ = pose.tipMm;
  contactForceN_ = glm::dvec3(0.0);
  lastGapMm_ = gapRate_ = glm::dvec3(0.0);
  lastTwistRad_ = twistRate_ = glm::dvec3(0.0);
}

double ProxyCoupling::displacementBoundMm(const ToolPose& a, const ToolPose& b) const {
  // No point of the tool travels farther than the tip does plus the turn at the farthest point.
  return glm::length(b.tipMm - a.tipMm) + angleBetween(a.orientation, b.orientation) * reachMm_;
}

double ProxyCoupling::boneInsideInnerLayer(const ToolPose& pose, int part, double radiusMm) {
  const ToolPart& tp = sim_->tool().parts[std::size_t(part)];
  const CoreSegment core(pose, tp);
  const double r = radiusMm > 0.0 ? radiusMm : tp.innerRadiusMm;
  double fill = 0.0;
  forEachSampleNearCore(sim_->voxels(), core, r,
                        [&](const geometry::VoxelSample& s) { fill += double(s.fill); });
  return fill;
}

bool ProxyCoupling::gather(const ToolPose& from, double reachMm) {
  const Tool& tool = sim_->tool();
  bool any = false;
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    PartCandidates& pc = candidates_[std::size_t(p)];
    pc.samples.clear();
    pc.complete = true;
    pc.allowance = 0.0;
    const CoreSegment core(from, part);
    const double admit = admitRadiusMm_[std::size_t(p)];
    const double inner2 = admit * admit;
    forEachSampleNearCore(sim_->voxels(), core, admit + reachMm,
                          [&](const geometry::VoxelSample& s) {
                            if (s.fill == 0) return;
                            const double d2 = core.distance2(s.centreMm);
                            if (d2 <= inner2)
                              pc.allowance += double(s.fill) * (admit - std::sqrt(d2));
                            if (pc.samples.size() < pc.samples.capacity()) {
                              pc.samples.push_back({s.centreMm, double(s.fill)});
                            } else {
                              pc.complete = false;
                            }
                          });
    any = any || !pc.samples.empty();
  }
  return any;
}

double ProxyCoupling::insideFill(const ToolPose& pose, int part) {
  const PartCandidates& pc = candidates_[std::size_t(part)];
  if (!pc.complete) {
    ++totals_.slowTests;
    return walkedPenetration(pose, part);
  }
  const CoreSegment core(pose, sim_->tool().parts[std::size_t(part)]);
  const double inner2 = admitRadiusMm_[std::size_t(part)] * admitRadiusMm_[std::size_t(part)];
  double fill = 0.0;
  for (const Candidate& c : pc.samples) {
    const double d2 = core.distance2(c.centreMm);
    if (d2 <= inner2) fill += c.fill * (admitRadiusMm_[std::size_t(part)] - std::sqrt(d2));
  }
  return fill;
}

bool ProxyCoupling::admissible(const ToolPose& pose) {
  // No part moves further into bone: the fill-weighted depth of the bone inside the parts'
  // inner layers may not grow. A pose that touches or holds a sample (after a cut off the
  // tool's axis, or a refinement split) may then move on along it or out of it; a count of
  // samples held would refuse a move that brushes one more while leaving another.
  const Tool& tool = sim_->tool();
  double depth = 0.0, allowance = 0.0;
  for (int p = 0; p < tool.partCount; ++p) {
    const PartCandidates& pc = candidates_[std::size_t(p)];
    if (pc.samples.empty()) continue;
    depth += insideFill(pose, p);
    allowance += pc.allowance;
  }
  // A millionth of a full finest sample's millimetre: the sums' rounding, not a sinking.
  return depth <= allowance + 1e-6 * (1.0 + allowance);
}

double ProxyCoupling::walkedPenetration(const ToolPose& pose, int part) {
  const CoreSegment core(pose, sim_->tool().parts[std::size_t(part)]);
  const double r = admitRadiusMm_[std::size_t(part)];
  double depth = 0.0;
  forEachSampleNearCore(sim_->voxels(), core, r, [&](const geometry::VoxelSample& s) {
    const double d2 = core.distance2(s.centreMm);
    if (s.fill != 0 && d2 <= r * r) depth += double(s.fill) * (r - std::sqrt(d2));
  });
  return depth;
}

glm::dvec3 ProxyCoupling::blockingNormal(const ToolPose& lo, const ToolPose& hi) const {
  // The constraint plane of this block: the samples the move's end takes deeper into a part's
  // inner layer than its start (the ones that stop it), each pushing from its centre toward
  // the part's core. A normal averaged over the whole shell points out of a hole cut a little
  // off the tool's axis, and the slide along it never clears the one sample on the wall.
  const Tool& tool = sim_->tool();
  glm::dvec3 sum(0.0);
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    const CoreSegment low(lo, part), high(hi, part);
    const double r = admitRadiusMm_[std::size_t(p)], r2 = r * r;
    for (const Candidate& c : candidates_[std::size_t(p)].samples) {
      glm::dvec3 toCore;
      const double dh2 = high.distance2(c.centreMm, &toCore);
      if (dh2 > r2 || !(dh2 > 0.0)) continue;
      // Deeper at hi than at lo (or newly inside): weighted by how much deeper.
      const double dl = std::min(r, std::sqrt(low.distance2(c.centreMm)));
      const double dh = std::sqrt(dh2);
      if (!(dh < dl)) continue;
      sum += (c.fill * (dl - dh) / dh) * toCore;
    }
  }
  const double len = glm::length(sum);
  return len > 0.0 && std::isfinite(len) ? sum / len : outwardNormal(hi);
}

glm::dvec3 ProxyCoupling::outwardNormal(const ToolPose& pose) const {
  // As eq. (1): the mean direction from the bone gathered near the block to the tool's core,
  // over a patch a few samples wide, so the contact plane does not follow single samples.
  const Tool& tool = sim_->tool();
  glm::dvec3 sum(0.0);
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    const CoreSegment core(pose, part);
    for (const Candidate& c : candidates_[std::size_t(p)].samples) {
      glm::dvec3 toCore;
      const double d2 = core.distance2(c.centreMm, &toCore);
      if (d2 > 0.0) sum += (c.fill / std::sqrt(d2)) * toCore;
    }
  }
  const double len = glm::length(sum);
  return len > 0.0 && std::isfinite(len) ? sum / len : glm::dvec3(0.0);
}

ProxyCoupling::MoveResult ProxyCoupling::constrainedMove(const ToolPose& to) {
  MoveResult result;
  const ToolPose from = proxy_;
  const double disp = displacementBoundMm(from, to);
  if (!(disp > 0.0)) {
    proxy_ = to;
    return result;
  }
  // Sub-moves no longer than half the thinnest part: no bone is jumped. A command farther than
  // kMaxSubMoves of them (a jump) is followed over the next steps.
  int n = int(std::ceil(disp / subMoveMm_));
  double tEnd = 1.0;
  if (n > kMaxSubMoves) {
    n = kMaxSubMoves;
    tEnd = double(kMaxSubMoves) * subMoveMm_ / disp;
  }
  double t0 = 0.0;
  for (int s = 1; s <= n; ++s) {
    const double t1 = s == n ? tEnd : tEnd * double(s) / double(n);
    // Every sample a part can meet in this sub-move lies within its travel of the inner layer.
    if (!gather(interpolate(from, to, t0), disp * (t1 - t0) * (1.0 + 1e-9) + 1e-9)) {
      t0 = t1;
      continue;
    }
    if (admissible(interpolate(from, to, t1))) {
      t0 = t1;
      continue;
    }
    // Held against the bone (most blocked steps), the bisection's answer is the sub-move's
    // start: one test of its first 1/2^kBisections says so in place of kBisections.
    const double first = t0 + (t1 - t0) / double(1 << kBisections);
    double lo = t0, hi = first;
    if (admissible(interpolate(from, to, first))) {
      lo = first;
      hi = t1;
    }
    for (int k = 0; k < kBisections && lo > t0; ++k) {
      const double mid = 0.5 * (lo + hi);
      if (admissible(interpolate(from, to, mid))) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
    proxy_ = interpolate(from, to, lo);
    result.blocked = true;
    result.normal = outwardNormal(interpolate(from, to, hi));
    result.blockingNormal = blockingNormal(interpolate(from, to, lo), interpolate(from, to, hi));
    return result;
  }
  proxy_ = interpolate(from, to, t0);
  if (t0 < 1.0) ++totals_.lagSteps;
  return result;
}

void ProxyCoupling::slide(const ToolPose& to, const glm::dvec3& firstNormal) {
  // The god-object's slide over up to 3 constraint planes (Zilles & Salisbury; CHAI3D): along
  // the first plane; blocked again, along the line where it meets the second; a third block
  // is a corner and holds the proxy. Each plane is that block's own (blockingNormal).
  if (!(displacementBoundMm(proxy_, to) > 1e-6)) return;
  const MoveResult second = constrainedMove(to);
  if (!second.blocked || second.blockingNormal == glm::dvec3(0.0)) return;
  const glm::dvec3 rest = to.tipMm - proxy_.tipMm;
  glm::dvec3 next(0.0);
  const glm::dvec3 line = glm::cross(firstNormal, second.blockingNormal);
  const double lineLen = glm::length(line);
  if (lineLen > 1e-3) {
    const glm::dvec3 u = line / lineLen;
    next = glm::dot(rest, u) * u;
  } else {
    // The same plane again (a curved wall): along it once more.
    const double into = glm::dot(rest, second.blockingNormal);
    if (into < 0.0) next = rest - into * second.blockingNormal;
  }
  const ToolPose along{proxy_.tipMm + next, to.orientation};
  if (displacementBoundMm(proxy_, along) > 1e-6) constrainedMove(along);
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

  // The layers the proxy is held out of: a cutting part's narrowed while its cut runs ahead.
  const Tool& tool = sim_->tool();
  for (int p = 0; p < tool.partCount; ++p) {
    const ToolPart& part = tool.parts[std::size_t(p)];
    const double ahead =
        part.cuts && commanded.drillOn ? std::min(cutAdvanceMm_, 0.5 * part.innerRadiusMm) : 0.0;
    admitRadiusMm_[std::size_t(p)] =
        std::sqrt(part.innerRadiusMm * part.innerRadiusMm - ahead * ahead);
  }
  // The proxy: as far toward the command as the bone lets it, then along the contact plane.
  const glm::dvec3 wasMm = proxy_.tipMm;
  const MoveResult move = constrainedMove(commanded.pose);
  if (move.blocked) {
    ++totals_.blockedSteps;
    const glm::dvec3 rest = cmdTip - proxy_.tipMm;
    const double into = glm::dot(rest, move.normal);
    const glm::dvec3 along = rest - into * move.normal;
    const double alongMm = glm::length(along);
    const double heldMm = options_.frictionCoefficient * std::max(0.0, -into);
    // Drawn back with the drill off (the command behind the proxy along the tool's axis), the
    // samples that block are not where the shell's plane says: a sample on the wall of a hole
    // cut off the tool's axis (or split by refinement) while the motion leaves the bone as a
    // whole. Slide over their own planes, up to 3, so the tool backs out the way the hole
    // goes. Pushed in, or cutting, along the shell's plane as before.
    const bool drawnBack = glm::dot(rest, proxy_.forward()) < 0.0;
    if (drawnBack && !commanded.drillOn) {
      const glm::dvec3 nb = move.blockingNormal;
      const double intoB = glm::dot(rest, nb);
      const glm::dvec3 alongB = rest - intoB * nb;
      const double alongBMm = glm::length(alongB);
      const double heldBMm = options_.frictionCoefficient * std::max(0.0, -intoB);
      if (intoB < 0.0 && alongBMm > heldBMm)
        slide({proxy_.tipMm + (1.0 - heldBMm / alongBMm) * alongB, commanded.pose.orientation}, nb);
    } else if (into < 0.0 && alongMm > heldMm) {
      const ToolPose slideTo{proxy_.tipMm + (1.0 - heldMm / alongMm) * along,
                             commanded.pose.orientation};
      if (displacementBoundMm(proxy_, slideTo) > 1e-6) constrainedMove(slideTo);
    }
    // Cutting, toward the command no faster than the feed limit: the rest of the step's
    // progress is taken back, toward where the proxy was (a slide along a plane a little off
    // the hole's wall would otherwise carry it down the freshly cut hole).
    const glm::dvec3 toward = cmdTip - wasMm;
    const double towardMm = glm::length(toward);
    if (commanded.drillOn && towardMm > 0.0) {
      const glm::dvec3 u = toward / towardMm;
      const double progressMm = glm::dot(proxy_.tipMm - wasMm, u);
      const double feedMm = options_.maxFeedMmPerS * dtS;
      if (progressMm > feedMm) proxy_.tipMm -= (progressMm - feedMm) * u;
    }
  }
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
  h.step = sim_->step({commanded.tS, h.stepPose, commanded.drillOn});

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

  ++totals_.steps;
  totals_.clampSteps += h.clamped ? 1 : 0;
  totals_.maxGapMm = std::max(totals_.maxGapMm, h.gapMm);
  return h;
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
