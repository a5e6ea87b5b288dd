// A number as messages print it: the stream's default form, shortest for the value's size
// ("0.3", "3e+300", "1.2e+09"), written once for every module's messages.
#pragma once

#include <sstream>
#include <string>

namespace osteon {

inline std::string numberText(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace osteon
