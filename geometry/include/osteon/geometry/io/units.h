// Length units. osteon works in millimetres inside; every loader is told the unit of its
// file (or a scale) and never guesses.
#pragma once

#include <string>

namespace osteon::geometry {

enum class LengthUnit { Millimetre, Centimetre, Metre, Inch };

// Millimetres in one unit: 1, 10, 1000, 25.4.
double millimetresPer(LengthUnit unit);

// Parses "mm", "cm", "m", "in"; throws InputError naming the value otherwise.
LengthUnit parseLengthUnit(const std::string& text);

const char* unitName(LengthUnit unit);

// When a bone's largest extent (mm, after loading with scaleToMm) is under 1 mm or over 2 m,
// it was most likely read in the wrong unit: returns the advice that brings it to 10..1000 mm,
// e.g. "a bone 0.361 mm across looks like metres read as millimetres: try --units m".
// Empty when the extent is plausible or no unit fits.
std::string unitsAdvice(double largestExtentMm, double scaleToMm = 1.0);

}  // namespace osteon::geometry
