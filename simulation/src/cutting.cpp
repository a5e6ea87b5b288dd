// The calibrated cutting resistance (cutting.h) and its fit to the published rows.
#include "osteon/simulation/cutting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "osteon/core/number_text.h"
#include "osteon/core/option_error.h"

namespace osteon::simulation {

ForceModelKind parseForceModelKind(const std::string& text) {
  if (text == "seed") return ForceModelKind::Seed;
  if (text == "calibrated") return ForceModelKind::Calibrated;
  throw OptionError("forceModel", text, "seed or calibrated");
}

const char* forceModelKindName(ForceModelKind kind) {
  return kind == ForceModelKind::Seed ? "seed" : "calibrated";
}

void validateRpm(double rpm) {
  if (!(rpm >= kMinRpm && rpm <= kMaxRpm)) {
    throw OptionError("drill.rpm", numberText(rpm), "revolutions per minute, 100 to 100000");
  }
}

double ThrustModel::thrustN(double rhoGcm3, double diameterMm, double feedMmPerS,
                            double rpm) const {
  const double above = rhoGcm3 - rho0Gcm3;
  if (!(above > 0.0) || !(feedMmPerS > 0.0) || !(rpm > 0.0)) return 0.0;
  const double perRevMm = 60.0 * feedMmPerS / rpm;
  return kNPerGcm3 * above * (diameterMm / refDiameterMm) *
         std::pow(perRevMm / refFeedPerRevMm, alpha);
}

double ThrustModel::feedMmPerS(double thrust, double rhoGcm3, double diameterMm, double rpm) const {
  const double above = rhoGcm3 - rho0Gcm3;
  if (!(above > 0.0)) return std::numeric_limits<double>::infinity();
  if (!(thrust > 0.0) || !(rpm > 0.0) || !(diameterMm > 0.0)) return 0.0;
  const double atRef = kNPerGcm3 * above * (diameterMm / refDiameterMm);
  return std::pow(thrust / atRef, 1.0 / alpha) * refFeedPerRevMm * rpm / 60.0;
}

double apparentDensityGcm3(double density) {
  const double slope = (kCorticalGcm3 - kCancellousGcm3) / (40.0 - 15.0);
  return std::max(0.05, kCancellousGcm3 + slope * (density - 15.0));
}

const std::vector<ThrustRow>& publishedThrustRows() {
  static const std::vector<ThrustRow> rows = {
      {"human femur, cortical", "MacAvelia et al. 2012", kCorticalGcm3, 3.2, 1000, 2, 198},
      {"human femur, cortical", "MacAvelia et al. 2012", kCorticalGcm3, 3.2, 1250, 2, 181},
      {"human femur, cortical", "MacAvelia et al. 2012", kCorticalGcm3, 3.2, 1500, 2, 176},
      {"Sawbones femur", "MacAvelia et al. 2012", -1, 3.2, 1000, 2, 87},
      {"Sawbones femur", "MacAvelia et al. 2012", -1, 3.2, 1250, 2, 82},
      {"Sawbones femur", "MacAvelia et al. 2012", -1, 3.2, 1500, 2, 76},
      {"bovine femur", "J Healthc Eng 2020", -1, 2.5, 1000, -1, 20.1},
      {"bovine femur", "J Healthc Eng 2020", -1, 2.5, 1500, -1, 12.3},
      {"porcine femur", "J Healthc Eng 2020", -1, 2.5, 1000, -1, 11.3},
      {"porcine femur", "J Healthc Eng 2020", -1, 2.5, 1500, -1, 8.1},
      // Settings not given: taken at the reference (3.2 mm, 1000 rpm, 2 mm/s); 1-1.5 N.
      {"human trochanter, cancellous", "Tsai et al.", kCancellousGcm3, 3.2, 1000, 2, 1.25}};
  return rows;
}

ThrustFit fitThrustModel(const std::vector<ThrustRow>& rows) {
  // alpha: one slope of log thrust against log rpm shared by every series (a material measured
  // at two or more rpm), each series with its own level.
  std::map<std::string, std::vector<std::size_t>> series;
  for (std::size_t i = 0; i < rows.size(); ++i) series[rows[i].material].push_back(i);
  double num = 0.0, den = 0.0;
  for (const auto& [material, idx] : series) {
    if (idx.size() < 2) continue;
    double xm = 0.0, ym = 0.0;
    for (const std::size_t i : idx) {
      xm += std::log(rows[i].rpm);
      ym += std::log(rows[i].thrustN);
    }
    xm /= double(idx.size());
    ym /= double(idx.size());
    for (const std::size_t i : idx) {
      num += (std::log(rows[i].rpm) - xm) * (std::log(rows[i].thrustN) - ym);
      den += (std::log(rows[i].rpm) - xm) * (std::log(rows[i].rpm) - xm);
    }
  }
  ThrustFit fit;
  ThrustModel& m = fit.model;
  if (den > 0.0) m.alpha = -num / den;
  // Each series' level: its thrust at 1000 rpm (geometric mean over its rows).
  std::map<std::string, double> level;
  for (const auto& [material, idx] : series) {
    double sum = 0.0;
    for (const std::size_t i : idx)
      sum += std::log(rows[i].thrustN) + m.alpha * std::log(rows[i].rpm / 1000.0);
    level[material] = std::exp(sum / double(idx.size()));
  }
  // K and rho0: a line through the levels of the series of known density at the reference
  // settings (least squares over them; two series give the line through both).
  double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (const auto& [material, idx] : series) {
    const ThrustRow& r = rows[idx.front()];
    if (!(r.rhoGcm3 > 0.0) || !(r.feedMmPerS > 0.0)) continue;
    const double perRev = 60.0 * r.feedMmPerS / 1000.0;
    const double y = level[material] / ((r.diameterMm / m.refDiameterMm) *
                                        std::pow(perRev / m.refFeedPerRevMm, m.alpha));
    n += 1.0;
    sx += r.rhoGcm3;
    sy += y;
    sxx += r.rhoGcm3 * r.rhoGcm3;
    sxy += r.rhoGcm3 * y;
  }
  if (n >= 2.0 && n * sxx - sx * sx > 0.0) {
    m.kNPerGcm3 = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    m.rho0Gcm3 = -(sy - m.kNPerGcm3 * sx) / n / m.kNPerGcm3;
  }
  for (const ThrustRow& r : rows) {
    const double modelN = r.rhoGcm3 > 0.0 && r.feedMmPerS > 0.0
                              ? m.thrustN(r.rhoGcm3, r.diameterMm, r.feedMmPerS, r.rpm)
                              : level[r.material] * std::pow(r.rpm / 1000.0, -m.alpha);
    fit.modelN.push_back(modelN);
    fit.residual.push_back((modelN - r.thrustN) / r.thrustN);
  }
  return fit;
}

}  // namespace osteon::simulation
