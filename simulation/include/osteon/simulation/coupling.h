// The proxy (god-object) coupling: the simulated tool is what the bone acts on, and the
// commanded pose (device, mouse, recording, path) pulls it through a virtual coupling, a
// spring-damper (Zilles & Salisbury 1995; McNeely, Puterbaugh & Troy 1999; CHAI3D's finger
// proxy; iMSTK's rigid tool joined to the device at 1 kHz). It sits above
// DrillingSimulation::step, which it calls with the proxy's pose.
//
// Rules, each 1 ms step, given the commanded pose and drillOn:
// - Admissible pose: no bone sample (a level-0 voxel or refined sub-voxel with fill) has its
//   centre inside any part's inner layer; the cushion (inner..outer) may hold bone, as it does
//   in contact. No part moves further into bone: a move may not deepen the fill-weighted depth
//   of the bone inside the parts' inner layers, so a pose that touches or holds samples (a hole
//   cut off the tool's axis, samples a refinement split) may move along or out of them.
//   While the drill cuts a cushion's advance a ahead, the cutting part's layer is tested at
//   sqrt(r_i^2 - a^2): the cut sphere
//   then holds every sample the proxy's front could meet, so no ring of bone at the hole's
//   rim, beside the cut, stops the tool (a cutting part's layer may hold bone up to r_i there).
// - The proxy moves along lerp(position)/slerp(orientation) from where it was to the command,
//   to the furthest admissible pose (sub-moves no longer than half the thinnest part, so thin
//   bone is not jumped, then a fixed count of bisections), then slides: the motion left is
//   projected on the contact plane, less a friction cone, and moved along the same way, so it
//   does not stick. Drawn back with the drill off (the command behind the proxy along its
//   axis), the slide uses the planes of the samples that block the move instead, up to 3 (the
//   motion left projected on two planes' line), so the tool backs out the way its hole goes.
// - In free space it reaches the command exactly. Into bone it moves no faster than the feed
//   limit (CouplingOptions::maxFeedMmPerS).
// - The drill on, DrillingSimulation::step runs at the proxy advanced toward the command by at
//   most the cutting part's cushion (and half its inner radius; ramped in over cutRampS), so
//   the tip eats its way in as the density decrements; the drill off, it runs at the proxy and
//   nothing is removed.
// - Force to the device = k (anchor - command) + b d/dt(anchor - command) + the contact force
//   of the step (seed 3.5, eqs. 1-2, slew-limited), clamped to N_max; the anchor is the proxy's
//   position, followed at most CouplingOptions::anchorSpeedMmPerS. Continuous at contact onset
//   and release: the gap grows from zero, the anchor never jumps, the gap rate is low-passed.
// - step() allocates nothing, locks nothing, throws nothing.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "osteon/simulation/drilling.h"
#include "osteon/simulation/thermal.h"

namespace osteon::simulation {

enum class CouplingMode { Direct, Proxy };

// Parses "proxy" or "direct"; throws InputError naming the value otherwise.
CouplingMode parseCouplingMode(const std::string& text);
const char* couplingModeName(CouplingMode mode);

struct CouplingOptions {
  // 0.5 N/mm: inside the 0.4-1 N/mm a Geomagic Touch renders stably, at its soft end so that
  // the spring reaches N_max (3.3 N) only 6.6 mm behind the command (the hand feels the spring
  // grow before the clamp), and well under the Touch's weakest axis rating (z, about 1 N/mm).
  double stiffnessNPerMm = 0.5;
  // The mass the spring is critically damped for: a stylus and the hand's grip, about 50 g.
  double virtualMassKg = 0.05;
  // < 0: critically damped for virtualMassKg, 2 sqrt(k m) = 0.01 N s/mm at the defaults, far
  // above Colgate & Schenkel's passivity floor k T / 2 = 0.00025 N s/mm at T = 1 ms.
  double dampingNsPerMm = -1.0;
  // Orientation: a torsion spring (N mm per rad), critically damped for the stylus's inertia
  // about the tip (kg mm^2; 50 g at 30 mm). Reported as the coupling torque; a 3-DOF device
  // such as the Touch renders no torque, so it is not sent.
  double rotationalStiffnessNmmPerRad = 50.0;
  double rotationalInertiaKgMm2 = 45.0;
  double rotationalDampingNmmSPerRad = -1.0;  // < 0: critically damped
  // The gap rate's low-pass time constant (s): a damping force that does not step at contact.
  double rateFilterS = 0.01;
  // The spring's anchor follows the proxy at most this fast (mm/s) while the proxy is off the
  // command: bone goes a sample layer at a time, so the proxy advances and slides in hops of
  // up to a sample (0.3 mm); the hand feels each as a slope of at most k x this speed
  // (0.025 N per ms at the defaults), not a step. It also follows the proxy back onto the command.
  double anchorSpeedMmPerS = 50.0;
  // The contact force's fastest change (N/s): 0.03 N per 1 ms step, so that with the anchor's
  // slope the force sent never steps by 0.1 N in a step.
  double contactSlewNPerS = 30.0;
  // The friction cone of the slide (Melder & Harwin's god-object with friction): of the motion
  // left along the contact plane, the part within mu x the push into the bone is held. Without
  // it a contact normal a degree off, times a gap of millimetres, slides the proxy about in a
  // hole by a tenth of a millimetre a step.
  double frictionCoefficient = 0.3;
  // The fastest the drill feeds into bone (mm/s), however hard it is pushed: the seed's removal
  // (one density unit per step) clears cancellous bone ahead of the cut at up to 50 mm/s, a
  // plunge no burr makes; 5 mm/s is about twice the seed's scripted portal paths (2.8 mm/s).
  double maxFeedMmPerS = 5.0;
  // Time (s) over which the cut pose moves out to its full advance when the drill turns on
  // (and back when it turns off), so the contact force does not jump then.
  double cutRampS = 0.05;
  // Bone samples gathered per part for one sub-move's tests; more are tested by walking the
  // hierarchy at each test (counted in CouplingTotals::slowTests).
  std::size_t candidateCapacity = 16384;
  // The cutting resistance (cutting.h). Seed: the seed's eq. (2) and the feed limit above.
  // Calibrated: while the drill cuts, the proxy feeds into bone no faster than the thrust law
  // gives for the force the device pushes along the tool (the last step's, back to real
  // newtons by kDeviceNPerRealN) in the bone ahead of the tip, at the step's rpm; the feed
  // limit above stays the ceiling, and the cutting parts' shells give no eq. (2) force.
  ForceModelKind forceModel = ForceModelKind::Seed;
  ThrustModel thrust;
  // The bone before drilling, whose density ahead of the tip is the material being cut (the
  // drilled grid's density is worn down as it is cut). Required for Calibrated.
  const geometry::VoxelGrid* materialGrid = nullptr;
  // Calibrated: the heat of each cutting step goes into this model (thermal.h; its deposit is
  // lock-free), and its tip temperature into the step's temperatureC. Null: no heat.
  ThermalModel* thermal = nullptr;
};

// Throws InputError naming the option for non-positive or non-finite values.
void validateCouplingOptions(const CouplingOptions& options);

// What one haptic step gave, in either mode.
struct HapticStep {
  StepOutput step;         // the simulation's step (contact at stepPose)
  ToolPose commanded;      // the device's (or path's) pose
  ToolPose proxy;          // the simulated tool (direct: the commanded pose)
  ToolPose stepPose;       // the pose step() ran at
  glm::dvec3 forceN{0.0};  // sent to the device: coupling + contact, clamped
  double magnitudeN = 0.0;
  glm::dvec3 torqueNmm{0.0};  // the rotational coupling's torque (not rendered)
  double gapMm = 0.0;         // |proxy tip - commanded tip|
  bool clamped = false;       // the force was at N_max
  // The calibrated model's (zero under the seed's): the bone ahead of the tip (g/cm3, 0: none),
  // the thrust the device pushed with in real newtons, and the feed that allowed (mm/s).
  double densityGcm3 = 0.0;
  double thrustRealN = 0.0;
  double feedLimitMmPerS = 0.0;
  double temperatureC = 37.0;  // at the tip, as the heat model last published it
};

struct CouplingTotals {
  std::uint64_t steps = 0;
  std::uint64_t clampSteps = 0;       // steps whose force was at N_max
  std::uint64_t blockedSteps = 0;     // steps where bone stopped the proxy
  std::uint64_t lagSteps = 0;         // commands too far for one step's sub-moves (a jump)
  std::uint64_t slowTests = 0;        // tests past the candidate capacity (walked instead)
  std::uint64_t nonFiniteForces = 0;  // zero force sent in place of a NaN or Inf
  double maxGapMm = 0.0;
};

class ProxyCoupling {
 public:
  // The simulation must outlive this object. Allocates its candidate buffers here.
  ProxyCoupling(DrillingSimulation& sim, const CouplingOptions& options = {});

  // One haptic step: moves the proxy, steps the simulation, gives the device's force.
  // No allocation, no lock, no throw.
  HapticStep step(const StepInput& commanded);

  // Puts the proxy at `pose` at rest (the next step starts from it).
  void reset(const ToolPose& pose);

  const ToolPose& proxy() const { return proxy_; }
  const CouplingOptions& options() const { return options_; }
  double dampingNsPerMm() const { return dampingNsPerMm_; }
  double rotationalDampingNmmSPerRad() const { return rotationalDamping_; }
  const CouplingTotals& totals() const { return totals_; }
  // Fill (grid fill units) of the bone samples whose centres lie inside part `part`'s inner
  // layer at `pose` (radiusMm > 0: that radius instead). Walks the hierarchy; no allocation.
  double boneInsideInnerLayer(const ToolPose& pose, int part, double radiusMm = -1.0);
  // The radius the last step tested part `part`'s layer at (see above).
  double admittedRadiusMm(int part) const { return admitRadiusMm_[std::size_t(part)]; }

  // Sub-moves and bisections per constrained move: fixed, so a step's work is bounded.
  static constexpr int kMaxSubMoves = 8;
  static constexpr int kBisections = 8;

 private:
  struct Candidate {
    glm::dvec3 centreMm;
    double fill;
  };
  struct PartCandidates {
    std::vector<Candidate> samples;  // reserved once
    bool complete = true;            // false: more than capacity, walk at each test
    double allowance = 0.0;          // fill-weighted depth already inside at the sub-move's start
  };
  struct MoveResult {
    bool blocked = false;
    glm::dvec3 normal{0.0};          // outward from the bone at the block (unit, or zero)
    glm::dvec3 blockingNormal{0.0};  // outward from the samples that block (unit, or zero)
  };

  // The step's move of the proxy toward the command (coupling_move.cpp).
  void moveProxy(const StepInput& commanded, double dtS);
  // Moves proxy_ toward `to` as far as admissible.
  MoveResult constrainedMove(const ToolPose& to);
  // Gathers each part's samples within reach of its inner layer at `from`; false when no
  // part has any (the sub-move is free).
  bool gather(const ToolPose& from, double reachMm);
  bool admissible(const ToolPose& pose);
  // Fill-weighted depth (fill x mm) of the bone inside part's inner layer at pose.
  double insideFill(const ToolPose& pose, int part);
  double walkedPenetration(const ToolPose& pose, int part);
  glm::dvec3 outwardNormal(const ToolPose& pose) const;
  // The outward normal of the samples that entered a part's inner layer between lo and hi.
  glm::dvec3 blockingNormal(const ToolPose& lo, const ToolPose& hi) const;
  // Slides proxy_ toward `to` over up to 3 constraint planes, the first `firstNormal`.
  void slide(const ToolPose& to, const glm::dvec3& firstNormal);
  double displacementBoundMm(const ToolPose& a, const ToolPose& b) const;

  DrillingSimulation* sim_;
  CouplingOptions options_;
  double dampingNsPerMm_;
  double rotationalDamping_;
  double subMoveMm_;  // half the thinnest part's inner radius
  double reachMm_;    // farthest point of any part from the tip (for rotations)
  double cushionMm_;  // the cut's lead: the cutting part's cushion, at most half its inner radius
  double cutterRadiusMm_ = 0.0;   // the cutting part's inner radius (the drill's, for the law)
  double feedLimitMmPerS_ = 0.0;  // this step's
  bool feedBoneAhead_ = false;    // calibrated: bone ahead of the cutter (the feed law applies)
  glm::dvec3 lastForceN_{0.0};    // the force sent last step
  // Calibrated: the feed limit of this step, from the thrust and the material ahead.
  void calibratedFeed(const StepInput& commanded, HapticStep& h);
  void admitLayers(bool drillOn);
  // The step's heat into options_.thermal (lock-free), and the tip temperature into h.
  void depositHeat(const StepInput& commanded, HapticStep& h, double dtS);
  std::array<PartCandidates, kMaxToolParts> candidates_;
  std::array<double, kMaxToolParts> admitRadiusMm_{};
  ToolPose proxy_;
  bool started_ = false;
  double lastS_ = 0.0;
  double cutAdvanceMm_ = 0.0;
  glm::dvec3 anchorMm_{0.0};
  glm::dvec3 contactForceN_{0.0};  // the slew-limited contact force
  glm::dvec3 lastGapMm_{0.0}, gapRate_{0.0};
  glm::dvec3 lastTwistRad_{0.0}, twistRate_{0.0};
  CouplingTotals totals_;
};

// The one haptic step every run mode takes: with a coupling, its step(); without one (direct
// coupling: the seed's scripted paths), the simulation at the commanded pose, its contact
// force to the device.
HapticStep stepHaptic(DrillingSimulation& sim, ProxyCoupling* coupling, const StepInput& commanded);

}  // namespace osteon::simulation
