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

}  // namespace osteon::geometry
