// `osteon experiment thrust` (docs/feel.md): blocks of cortical and cancellous bone drilled
// straight down at the published settings (drill diameter, rpm, feed), the command moving at
// the feed and the hand's push growing until the proxy keeps pace. The steady thrust, the force
// the device pushes with along the tool while the tip feeds at the commanded rate, is compared
// with the published figure (before and after kDeviceNPerRealN) and with the seed's model.
#pragma once

#include <string>
#include <vector>

#include "osteon/simulation/cutting.h"
#include "osteon/simulation/force_log.h"

namespace osteon::simulation {

struct ThrustCase {
  std::string material;  // "cortical" or "cancellous"
  double density = 40;   // the grid's drilling difficulty (density.h): 40 cortical, 15 cancellous
  double diameterMm = 3.2, rpm = 1000, feedMmPerS = 2;
  double publishedN = -1;  // the published thrust at these settings (< 0: none)
  std::string source;
  std::string name() const;  // e.g. "cortical_3.2mm_1000rpm_2mmps"
};

// Human cortical bone at 1000, 1250 and 1500 rpm and the cancellous row (the published ones),
// then cortical bone at 0.5 and 1 mm/s (the feed law; no published figure).
std::vector<ThrustCase> thrustExperimentCases();

struct ThrustResult {
  ThrustCase c;
  ForceModelKind model = ForceModelKind::Calibrated;
  double deviceN = 0.0;     // the mean push along the tool over the steady window (N, device)
  double realN = 0.0;       // deviceN / kDeviceNPerRealN
  double lawN = 0.0;        // the thrust law at the settings (real N)
  double feedMmPerS = 0.0;  // the tip's mean feed over the window
  double windowStartS = 0.0, windowEndS = 0.0;
  std::vector<ForceLogRow> log;  // every step (1 kHz)
};

// One block drilled at the case's settings under `model` (proxy coupling; the seed's model
// renders the same case for comparison). Deterministic.
ThrustResult runThrustCase(const ThrustCase& c, ForceModelKind model);

}  // namespace osteon::simulation
