// The proxy's move: sub-moves and bisections against the bone samples near the tool, the slide
// over the contact planes, the feed limit (coupling.h states the rules).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include "coupling_internal.h"
#include "osteon/simulation/coupling.h"

namespace osteon::simulation {

using detail::CoreSegment;
using detail::forEachSampleNearCore;
using detail::interpolate;

double ProxyCoupling::displacementBoundMm(const ToolPose& a, const ToolPose& b) const {
  // No point of the tool travels farther than the tip does plus the turn at the farthest point.
  return glm::length(b.tipMm - a.tipMm) +
         detail::angleBetween(a.orientation, b.orientation) * reachMm_;
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

// Moves the proxy toward the command: as far as the bone lets it, then along the contact plane
// (less a friction cone), then back to the feed limit while the drill cuts.
void ProxyCoupling::moveProxy(const StepInput& commanded, double dtS) {
  const glm::dvec3& cmdTip = commanded.pose.tipMm;
  const glm::dvec3 wasMm = proxy_.tipMm;
  // Cutting under the calibrated model, the proxy can go no further than the feed allows this
  // step: it tries that far, not the whole way to a command millimetres ahead (whose sub-moves
  // and gathered samples would be thrown away by the feed limit below).
  ToolPose target = commanded.pose;
  if (feedBoneAhead_ && commanded.drillOn) {
    const glm::dvec3 toCommand = cmdTip - wasMm;
    const double distanceMm = glm::length(toCommand), feedMm = feedLimitMmPerS_ * dtS;
    if (distanceMm > feedMm) target.tipMm = wasMm + (feedMm / distanceMm) * toCommand;
  }
  const MoveResult move = constrainedMove(target);
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
  }
  // Cutting, toward the command no faster than the feed limit: the rest of the step's
  // progress is taken back, toward where the proxy was (a slide along a plane a little off
  // the hole's wall would otherwise carry it down the freshly cut hole). The calibrated model
  // limits every move with bone ahead of the cutter, blocked or not: the cut ahead clears the
  // way, the thrust law sets the pace.
  if (!move.blocked && !(feedBoneAhead_ && commanded.drillOn)) return;
  const glm::dvec3 toward = cmdTip - wasMm;
  const double towardMm = glm::length(toward);
  if (commanded.drillOn && towardMm > 0.0) {
    const glm::dvec3 u = toward / towardMm;
    const double progressMm = glm::dot(proxy_.tipMm - wasMm, u);
    const double feedMm = feedLimitMmPerS_ * dtS;
    if (progressMm > feedMm) proxy_.tipMm -= (progressMm - feedMm) * u;
  }
}

}  // namespace osteon::simulation
