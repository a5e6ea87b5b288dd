// Augustin et al. 2008 (Arch Orthop Trauma Surg 128:71-77) rerun: twist drills of 2.5, 3.2 and
// 4.5 mm at 188, 462, 1140 and 1820 rpm drill through a cortical block, without and with
// irrigation (water at 26 °C), the thermal model (thermal.h) running beside the drilling
// simulation; the peak temperature where the paper's thermocouple sat, beside what it reports:
// 31.4-55.5 °C without irrigation, above 47 °C only with the 4.5 mm drill at 1140 and 1820 rpm,
// below 47 °C with irrigation; and the higher the feed, the lower the temperature.
// The settings the paper does not give are assumptions (docs/feel.md, "Heat").
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "osteon/simulation/thermal.h"

namespace osteon::simulation {

struct HeatSetting {
  double diameterMm = 0.0;
  double rpm = 0.0;
  double feedMmPerMin = 0.0;
  bool feedSeries = false;  // of the feed series, not of the speed x diameter grid
};

// What the paper reports for a setting: the range every setting without irrigation falls in,
// whether it passed 47 °C, and the feed series' order.
struct HeatPublished {
  double minC = 31.4, maxC = 55.5;  // without irrigation, over every setting
  double criticalC = 47.0;
  // Without irrigation: above 47 °C (the 4.5 mm drill at 1140 and 1820 rpm) or below.
  static bool aboveCritical(const HeatSetting& s) { return s.diameterMm > 4.0 && s.rpm > 1000.0; }
};

struct HeatExperimentOptions {
  ThermalOptions thermal;  // initialC and irrigationC: the room's 26 °C
  double cortexMm = 5.0;   // the block's thickness (a porcine femoral diaphysis)
  double blockMm = 12.0;   // its width and depth
  double voxelMm = 0.25;   // the drilled grid's voxels
  // The thermocouple, fixed for every drill as a fixture holds it: this far from the drill's
  // axis (0.5 mm from the widest hole's wall), at this depth below the entry surface.
  double thermocoupleFromAxisMm = 2.75;
  double thermocoupleDepthMm = 2.5;
  double afterS = 5.0;         // conduction simulated after the drill leaves the block
  int diffuseEverySteps = 10;  // diffuse() at 100 Hz, as a visual thread would
  HeatExperimentOptions();
};

struct HeatRun {
  HeatSetting setting;
  double thrustN = 0.0;     // real thrust (ThrustModel) at the setting
  double drillS = 0.0;      // time the path takes
  double removedMm3 = 0.0;  // bone the drill removed
  double depositedJ = 0.0;  // heat into the bone, without irrigation
  // Without [0] and with [1] irrigation: the thermocouple's peak, the grid's peak, the volume
  // past the damage dose.
  double peakC[2] = {0.0, 0.0};
  double gridPeakC[2] = {0.0, 0.0};
  double damagedMm3[2] = {0.0, 0.0};
  double damagedBoneMm3[2] = {0.0, 0.0};  // of the bone left around the hole
};

// The paper's speed x diameter grid at 84 mm/min, then the 4.5 mm drill at 1820 rpm at its
// four feeds (24, 56, 84 and 196 mm/min; 84 again, so the series reads whole).
std::vector<HeatSetting> augustinSettings();

// Drills each setting once (the deterministic driver: deposit every 1 kHz step, diffuse every
// diffuseEverySteps), feeding two thermal models, without and with irrigation. `progress`
// (may be empty) hears each run.
std::vector<HeatRun> runHeatExperiment(const std::vector<HeatSetting>& settings,
                                       const HeatExperimentOptions& options = {},
                                       const std::function<void(const HeatRun&)>& progress = {});

}  // namespace osteon::simulation
