// The thrust experiment (thrust_experiment.h): a bone block, a straight plunge at the feed.
#include "osteon/simulation/thrust_experiment.h"

#include <cmath>
#include <sstream>

#include "osteon/simulation/path.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

namespace {

constexpr double kVoxelMm = 0.25;
constexpr double kBlockMm[3] = {10.0, 10.0, 28.0};
constexpr double kAboveMm = 1.0;  // the tip starts this far above the block, the drill on
// The command moves at the feed for this long in bone: long enough for the spring to wind up
// (the gap a push needs, at 0.5 N/mm) and hold a steady window.
constexpr double kInBoneS = 12.0;

geometry::VoxelGrid block(double density) {
  const glm::ivec3 dims(int(kBlockMm[0] / kVoxelMm), int(kBlockMm[1] / kVoxelMm),
                        int(kBlockMm[2] / kVoxelMm));
  geometry::VoxelGrid grid(dims + 2, glm::dvec3(-kVoxelMm), kVoxelMm);
  for (int z = 1; z <= dims.z; ++z)
    for (int y = 1; y <= dims.y; ++y)
      for (int x = 1; x <= dims.x; ++x)
        grid.set({x, y, z}, geometry::kFillFull, geometry::Density(density));
  return grid;
}

}  // namespace

std::string ThrustCase::name() const {
  std::ostringstream s;
  s << material << "_" << diameterMm << "mm_" << rpm << "rpm_" << feedMmPerS << "mmps";
  return s.str();
}

std::vector<ThrustCase> thrustExperimentCases() {
  std::vector<ThrustCase> cases;
  for (const ThrustRow& r : publishedThrustRows()) {
    if (!(r.rhoGcm3 > 0.0) || !(r.feedMmPerS > 0.0)) continue;
    const bool cortical = r.rhoGcm3 == kCorticalGcm3;
    cases.push_back({cortical ? "cortical" : "cancellous", cortical ? 40.0 : 15.0, r.diameterMm,
                     r.rpm, r.feedMmPerS, r.thrustN, r.source});
  }
  for (const double feed : {0.5, 1.0}) cases.push_back({"cortical", 40, 3.2, 1000, feed, -1, ""});
  return cases;
}

ThrustResult runThrustCase(const ThrustCase& c, ForceModelKind model) {
  SessionOptions so;
  so.levels = 0;
  so.keepSurface = false;
  so.coupling = CouplingMode::Proxy;
  so.forceModel = model;
  so.settings.rpm = c.rpm;
  so.toolOptions.tipDiameterMm = c.diameterMm;
  Session session(BoneModel::fromGrid(block(c.density), "block"), so);
  // Straight down the block's centre, from above its top face.
  const glm::dvec3 top(0.5 * kBlockMm[0], 0.5 * kBlockMm[1], kBlockMm[2]);
  const glm::dquat down = ToolPose::pointing(top, glm::dvec3(0, 0, -1)).orientation;
  const double radiusMm = 0.5 * c.diameterMm;
  const glm::dvec3 start = top + glm::dvec3(0, 0, kAboveMm + radiusMm);
  const double approachS = (kAboveMm + radiusMm) / c.feedMmPerS;
  const double endS = approachS + kInBoneS;
  const DrillPath path({{0.0, start, down, true},
                        {endS, start - glm::dvec3(0, 0, c.feedMmPerS * endS), down, true}});
  ThrustResult r;
  r.c = c;
  r.model = model;
  r.lawN = ThrustModel{}.thrustN(apparentDensityGcm3(c.density), c.diameterMm, c.feedMmPerS, c.rpm);
  DeterministicOptions ro;
  ro.keepLog = true;
  r.log = session.run(path, ro).log;
  // The steady window: the last half of the time in bone.
  r.windowStartS = approachS + 0.5 * kInBoneS;
  r.windowEndS = endS;
  double push = 0.0, n = 0.0, z0 = 0.0, z1 = 0.0, t0 = -1.0, t1 = 0.0;
  for (const ForceLogRow& row : r.log) {
    if (row.tS < r.windowStartS) continue;
    push += -glm::dot(row.forceN, glm::dvec3(0, 0, -1));  // the force on the hand points up
    n += 1.0;
    if (t0 < 0.0) {
      t0 = row.tS;
      z0 = row.tipMm.z;
    }
    t1 = row.tS;
    z1 = row.tipMm.z;
  }
  r.deviceN = n > 0.0 ? push / n : 0.0;
  r.realN = r.deviceN / kDeviceNPerRealN;
  r.feedMmPerS = t1 > t0 ? (z0 - z1) / (t1 - t0) : 0.0;
  return r;
}

}  // namespace osteon::simulation
