// Checks of option values, written once so every option's message has one shape:
// "<name> <value>: must be a positive number".
#pragma once

#include <cmath>
#include <sstream>

#include "osteon/core/error.h"

namespace osteon {

// Throws InputError naming the option (with its unit, e.g. "coupling stiffness (N/mm)") and
// the value, unless the value is finite and greater than zero.
inline void requirePositive(double value, const char* name) {
  if (value > 0.0 && std::isfinite(value)) return;
  std::ostringstream s;
  s << name << " " << value << ": must be a positive number";
  throw InputError(s.str());
}

}  // namespace osteon
