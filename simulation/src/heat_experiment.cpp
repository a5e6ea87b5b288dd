#include "osteon/simulation/heat_experiment.h"

#include <algorithm>
#include <cmath>

#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/simulation/cutting.h"
#include "osteon/simulation/session.h"

namespace osteon::simulation {

HeatExperimentOptions::HeatExperimentOptions() {
  // Augustin et al. drilled at room temperature, irrigating with water at 26 °C (their 2009
  // thermography report names the room's 26 °C).
  thermal.initialC = 26.0;
  thermal.irrigationC = 26.0;
  thermal.cellMm = 0.25;
  thermal.marginMm = 1.0;  // the specimen's own bone around the block
}

std::vector<HeatSetting> augustinSettings() {
  std::vector<HeatSetting> settings;
  for (const double d : {2.5, 3.2, 4.5})
    for (const double rpm : {188.0, 462.0, 1140.0, 1820.0}) settings.push_back({d, rpm, 84.0});
  for (const double feed : {24.0, 56.0, 84.0, 196.0}) settings.push_back({4.5, 1820.0, feed, true});
  return settings;
}

namespace {

constexpr int kCortical = 40;  // the grid's drilling difficulty of cortical bone (density.h)

// A block of cortical bone, its entry surface at z = 0, cortexMm thick below it.
geometry::VoxelGrid corticalBlock(const HeatExperimentOptions& o) {
  const int side = int(std::ceil(o.blockMm / o.voxelMm));
  const int depth = int(std::ceil(o.cortexMm / o.voxelMm));
  const glm::dvec3 origin(-0.5 * double(side) * o.voxelMm, -0.5 * double(side) * o.voxelMm,
                          -double(depth) * o.voxelMm);
  geometry::VoxelGrid grid(glm::ivec3(side, side, depth), origin, o.voxelMm);
  for (int k = 0; k < depth; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        grid.set(glm::ivec3(i, j, k), geometry::kFillFull, geometry::Density(kCortical));
  return grid;
}

struct Thermocouple {
  glm::dvec3 pointMm;
  double peakC[2];
};

HeatRun runSetting(const HeatSetting& s, const geometry::VoxelGrid& block,
                   const HeatExperimentOptions& o) {
  SessionOptions so;
  so.levels = 0;
  so.keepSurface = false;
  so.toolOptions.tipDiameterMm = s.diameterMm;
  so.toolOptions.shaftDiameterMm = 0.8 * s.diameterMm;
  Session session = Session::fromGrid(block, so, "cortical block");
  DrillingSimulation& sim = session.simulation();
  const double rho = apparentDensityGcm3(double(kCortical));
  const double feedMmPerS = s.feedMmPerMin / 60.0;

  HeatRun run;
  run.setting = s;
  run.thrustN = ThrustModel{}.thrustN(rho, s.diameterMm, feedMmPerS, s.rpm);
  // Twin models fed the same steps: without [0] and with [1] irrigation.
  ThermalModel model0(block, o.thermal), model1(block, o.thermal);
  ThermalModel* models[2] = {&model0, &model1};
  Thermocouple tc{{o.thermocoupleFromAxisMm, 0.0, -o.thermocoupleDepthMm},
                  {o.thermal.initialC, o.thermal.initialC}};
  const double radius = 0.5 * s.diameterMm;
  // Straight down the z axis, from just above the block to through its far side.
  const double startZ = radius + 0.5, endZ = -o.cortexMm - radius - 0.5;
  run.drillS = (startZ - endZ) / feedMmPerS;
  const auto steps = long(std::ceil(run.drillS * 1000.0));
  const auto afterSteps = long(std::ceil(o.afterS * 1000.0));
  const double dt = 0.001;
  const double voxelMm3 = block.voxelVolumeMm3();
  for (long i = 0; i <= steps + afterSteps; ++i) {
    const bool drilling = i <= steps;
    const double z = std::max(endZ, startZ - feedMmPerS * double(i) * dt);
    HeatInput in;
    in.tipMm = glm::dvec3(0.0, 0.0, z);
    in.rhoGcm3 = rho;
    in.rpm = s.rpm;
    in.diameterMm = s.diameterMm;
    in.thrustN = run.thrustN;
    in.dtS = dt;
    if (drilling) {
      StepInput step(double(i) * dt, ToolPose::pointing(in.tipMm, glm::dvec3(0.0, 0.0, -1.0)), true,
                     DrillSettings{s.rpm, false});
      const StepOutput out = sim.step(step);
      in.removedMm3 = out.removal.removedVolumeMm3(voxelMm3);
      in.cutting = in.removedMm3 > 0.0 || out.contact.contactVoxels > 0.0;
      run.removedMm3 += in.removedMm3;
    }
    for (int m = 0; m < 2; ++m) {
      in.irrigation = m == 1;
      models[m]->deposit(in);
    }
    if ((i + 1) % o.diffuseEverySteps == 0) {
      for (int m = 0; m < 2; ++m) {
        models[m]->diffuse(dt * double(o.diffuseEverySteps));
        tc.peakC[m] = std::max(tc.peakC[m], models[m]->temperatureAtC(tc.pointMm));
      }
    }
  }
  for (int m = 0; m < 2; ++m) {
    run.peakC[m] = tc.peakC[m];
    run.gridPeakC[m] = models[m]->peakC();
    run.damagedMm3[m] = models[m]->damagedVolumeMm3();
    run.damagedBoneMm3[m] = models[m]->damagedBoneVolumeMm3(sim.grid());
  }
  run.depositedJ = model0.depositedJ();
  return run;
}

}  // namespace

std::vector<HeatRun> runHeatExperiment(const std::vector<HeatSetting>& settings,
                                       const HeatExperimentOptions& options,
                                       const std::function<void(const HeatRun&)>& progress) {
  validateThermalOptions(options.thermal);
  const geometry::VoxelGrid block = corticalBlock(options);
  std::vector<HeatRun> runs;
  runs.reserve(settings.size());
  for (const HeatSetting& s : settings) {
    runs.push_back(runSetting(s, block, options));
    if (progress) progress(runs.back());
  }
  return runs;
}

}  // namespace osteon::simulation
