#include "osteon/geometry/io/units.h"

#include <cmath>
#include <sstream>

#include "osteon/core/option_error.h"

namespace osteon::geometry {

double millimetresPer(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Millimetre:
      return 1.0;
    case LengthUnit::Centimetre:
      return 10.0;
    case LengthUnit::Metre:
      return 1000.0;
    case LengthUnit::Inch:
      return 25.4;
  }
  return 1.0;
}

LengthUnit parseLengthUnit(const std::string& text) {
  if (text == "mm") return LengthUnit::Millimetre;
  if (text == "cm") return LengthUnit::Centimetre;
  if (text == "m") return LengthUnit::Metre;
  if (text == "in") return LengthUnit::Inch;
  throw OptionError("units", text, "unknown unit (expected mm, cm, m or in)");
}

double resolveScaleToMm(const std::string& units, const std::optional<double>& scale) {
  if (!scale) return millimetresPer(parseLengthUnit(units));
  if (!std::isfinite(*scale) || *scale <= 0.0) {
    std::ostringstream s;
    s << *scale;
    throw OptionError("scale", s.str(), "must be a positive finite number");
  }
  return *scale;
}

const char* unitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Millimetre:
      return "mm";
    case LengthUnit::Centimetre:
      return "cm";
    case LengthUnit::Metre:
      return "m";
    case LengthUnit::Inch:
      return "in";
  }
  return "mm";
}

std::string unitsAdvice(double largestExtentMm, double scaleToMm) {
  if (!(largestExtentMm > 0.0) || !std::isfinite(largestExtentMm) || !(scaleToMm > 0.0)) return "";
  if (largestExtentMm >= 1.0 && largestExtentMm <= 2000.0) return "";
  const double fileExtent = largestExtentMm / scaleToMm;  // in the file's own numbers
  const char* names[] = {"millimetres", "centimetres", "metres", "inches"};
  const LengthUnit units[] = {LengthUnit::Millimetre, LengthUnit::Centimetre, LengthUnit::Metre,
                              LengthUnit::Inch};
  // The unit that makes a humerus or femur-sized bone (about 30..500 mm) most plausible.
  int best = -1;
  double bestMiss = 0.0;
  for (int u = 0; u < 4; ++u) {
    const double mm = fileExtent * millimetresPer(units[u]);
    if (mm < 10.0 || mm > 1000.0 ||
        std::abs(millimetresPer(units[u]) - scaleToMm) < 1e-12 * scaleToMm)
      continue;
    const double miss = std::abs(std::log10(mm / 150.0));
    if (best < 0 || miss < bestMiss) best = u, bestMiss = miss;
  }
  if (best < 0) return "";
  std::ostringstream s;
  s << "a bone " << largestExtentMm << " mm across looks like " << names[best] << " read as ";
  const char* readAs = nullptr;
  for (int u = 0; u < 4; ++u) {
    if (std::abs(millimetresPer(units[u]) - scaleToMm) < 1e-12 * scaleToMm) readAs = names[u];
  }
  if (readAs) {
    s << readAs;
  } else {
    s << "a scale of " << scaleToMm;
  }
  s << ": try " << optionRef("units") << " " << unitName(units[best]);
  return s.str();
}

}  // namespace osteon::geometry
