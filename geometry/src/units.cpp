#include "osteon/geometry/units.h"

#include "osteon/geometry/error.h"

namespace osteon::geometry {

double millimetresPer(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Millimetre: return 1.0;
    case LengthUnit::Centimetre: return 10.0;
    case LengthUnit::Metre: return 1000.0;
    case LengthUnit::Inch: return 25.4;
  }
  return 1.0;
}

LengthUnit parseLengthUnit(const std::string& text) {
  if (text == "mm") return LengthUnit::Millimetre;
  if (text == "cm") return LengthUnit::Centimetre;
  if (text == "m") return LengthUnit::Metre;
  if (text == "in") return LengthUnit::Inch;
  throw InputError("--units " + text + ": unknown unit (expected mm, cm, m or in)");
}

const char* unitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::Millimetre: return "mm";
    case LengthUnit::Centimetre: return "cm";
    case LengthUnit::Metre: return "m";
    case LengthUnit::Inch: return "in";
  }
  return "mm";
}

}  // namespace osteon::geometry
