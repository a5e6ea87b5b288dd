// Length units. osteon works in millimetres inside; every loader is told the unit of its
// file (or a scale) and never guesses.
#pragma once

#include <optional>
#include <string>

namespace osteon::geometry {

enum class LengthUnit { Millimetre, Centimetre, Metre, Inch };

// Millimetres in one unit: 1, 10, 1000, 25.4.
double millimetresPer(LengthUnit unit);

// Parses "mm", "cm", "m", "in"; throws OptionError (field "units") naming the value otherwise.
LengthUnit parseLengthUnit(const std::string& text);

// Millimetres per coordinate of a mesh: `scale` when given, else the unit's. The one check of
// both: throws OptionError "scale 0: must be a positive finite number" (field "scale") or the
// unit's.
double resolveScaleToMm(const std::string& units,
                        const std::optional<double>& scale = std::nullopt);

const char* unitName(LengthUnit unit);

// When a bone's largest extent (mm, after loading with scaleToMm) is under 1 mm or over 2 m,
// it was most likely read in the wrong unit: returns the advice that brings it to 10..1000 mm,
// e.g. "a bone 0.361 mm across looks like metres read as millimetres: try --units m".
// Empty when the extent is plausible or no unit fits.
std::string unitsAdvice(double largestExtentMm, double scaleToMm = 1.0);

}  // namespace osteon::geometry
