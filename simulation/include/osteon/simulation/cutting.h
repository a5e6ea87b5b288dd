// The cutting resistance of bone, calibrated to published drilling experiments (docs/feel.md):
// the thrust a twist drill needs to feed into bone,
//   F = K (rho - rho0) (D / D_ref) (f_r / f_ref)^alpha,   f_r = 60 v / rpm  (mm per revolution)
// - a power law in the feed per revolution (Jacobs, Pope & Ilstrup 1976): faster feed, more
//   thrust; at a fixed feed, slower rpm means a thicker chip per revolution, more thrust;
// - linear in the bone's apparent density rho above a threshold rho0 (Ong & Bouazza-Marouf
//   2000), rho0 fitted so that cancellous bone, which the drill crumbles, needs ~1 N;
// - proportional to the drill's diameter (the cutting lips' length; not separable from the
//   species in the rows below, so not fitted).
// alpha is fitted to the four rpm series (MacAvelia 2012: human femur and Sawbones, 3.2 mm,
// 2 mm/s; J Healthc Eng 2020: bovine and porcine femur, 2.5 mm), each with its own level; K and
// rho0 to human cortical bone (1.85 g/cm3) and trochanteric cancellous bone (0.30 g/cm3, 1-1.5 N,
// Tsai et al.) at the reference settings. fitThrustModel() recomputes them from the table.
//
// The hand feels it through the proxy (coupling.h): under --force-model calibrated the proxy
// feeds into bone no faster than the feed this law gives for the thrust the device pushes with
// (scaled by kDeviceNPerRealN), so pushing harder feeds faster and cortex resists more than
// cancellous bone. --force-model seed keeps the seed's eq. (2) untouched.
#pragma once

#include <string>
#include <vector>

#include "osteon/geometry/voxels/voxel_grid.h"

namespace osteon::simulation {

enum class ForceModelKind { Seed, Calibrated };

// "seed" or "calibrated"; OptionError naming forceModel otherwise.
ForceModelKind parseForceModelKind(const std::string& text);
const char* forceModelKindName(ForceModelKind kind);

// The drill's motor and the irrigation, as the trainee sets them (knob, pedal, panel, --rpm,
// --irrigation) and as recordings carry them.
struct DrillSettings {
  double rpm = 1000.0;
  bool irrigation = false;
};
inline constexpr double kMinRpm = 100.0, kMaxRpm = 100000.0;
// OptionError naming drill.rpm unless it is within [kMinRpm, kMaxRpm].
void validateRpm(double rpm);

struct ThrustModel {
  double kNPerGcm3 = 136.19;  // K: N per g/cm3 above rho0, at the reference settings
  double rho0Gcm3 = 0.2908;   // density below which bone gives no thrust
  double alpha = 0.6639;      // the exponent of the feed per revolution
  double refDiameterMm = 3.2;
  double refFeedPerRevMm = 0.12;  // 2 mm/s at 1000 rpm

  // The thrust (N, real) to feed at feedMmPerS; 0 at or below rho0 or at zero feed.
  double thrustN(double rhoGcm3, double diameterMm, double feedMmPerS, double rpm) const;
  // The feed (mm/s) a thrust (N, real) gives: thrustN's inverse; +inf at or below rho0.
  double feedMmPerS(double thrustN, double rhoGcm3, double diameterMm, double rpm) const;
};

// Real thrust -> the device: human cortical bone at the reference settings (212 N as fitted)
// renders as 3.0 N, under the Touch's 3.3 N. Every ratio of real thrusts holds on the device.
inline constexpr double kDeviceNPerRealN = 3.0 / 212.34;

// The apparent density (g/cm3) of the grid's drilling difficulty d (density.h): linear through
// the seed's two materials, cortical d = 40 -> 1.85 g/cm3, cancellous d = 15 -> 0.30 g/cm3
// (floored at 0.05 below).
double apparentDensityGcm3(double density);
inline constexpr double kCorticalGcm3 = 1.85, kCancellousGcm3 = 0.30;

// One published measurement (docs/feel.md): feedMmPerS < 0 where the paper's table gives none.
struct ThrustRow {
  std::string material, source;
  double rhoGcm3 = 0.0;  // < 0: not bone (Sawbones) or not given: not used for K and rho0
  double diameterMm = 0.0, rpm = 0.0, feedMmPerS = 0.0, thrustN = 0.0;
};
const std::vector<ThrustRow>& publishedThrustRows();

struct ThrustFit {
  ThrustModel model;
  // Per row: the model's thrust at the row's settings (its series' own level where the row has
  // no density or feed), and (model - published) / published.
  std::vector<double> modelN, residual;
};
// alpha by least squares in log thrust over the rpm series (a level per series); K and rho0
// through the human cortical and cancellous levels at the reference settings.
ThrustFit fitThrustModel(const std::vector<ThrustRow>& rows);

}  // namespace osteon::simulation
