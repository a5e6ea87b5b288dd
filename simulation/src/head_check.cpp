// Whether a fitted sphere is a humeral head, and the up axis by name (path.h).
#include <cmath>
#include <string>

#include "osteon/core/number_text.h"
#include "osteon/core/option_error.h"
#include "osteon/simulation/path.h"

namespace osteon::simulation {

void checkHumeralHead(const HumeralHead& head, const std::string& name) {
  std::string why;
  if (head.radiusMm < kMinHeadRadiusMm || head.radiusMm > kMaxHeadRadiusMm) {
    why = "the sphere fitted at the bone's end has a radius of " + numberText(head.radiusMm) +
          " mm (a humeral head's is " + numberText(kMinHeadRadiusMm) + "-" +
          numberText(kMaxHeadRadiusMm) + " mm)";
  } else if (head.endGapMm > head.radiusMm) {
    why = "the sphere fitted lies " + numberText(head.endGapMm) +
          " mm inside the bone's end (a head's top is within its radius of it)";
  } else {
    const double share = head.capAreaMm2 / (4.0 * M_PI * head.radiusMm * head.radiusMm);
    if (!(share >= kMinHeadCapShare)) {
      why = "the surface on the sphere fitted covers " + numberText(100.0 * share) +
            " % of it (a head's articular cap covers " + numberText(100.0 * kMinHeadCapShare) +
            " % or more)";
    }
  }
  if (why.empty()) return;
  throw InputError(name + ": no humeral head: " + why + "; give the up axis (" + optionRef("up") +
                   " x|y|z|-x|-y|-z) or an explicit entry point");
}

glm::dvec3 parseUpAxis(const std::string& text) {
  const bool negative = !text.empty() && text[0] == '-';
  const std::string axis = negative ? text.substr(1) : text;
  const double sign = negative ? -1.0 : 1.0;
  if (axis == "x") return {sign, 0.0, 0.0};
  if (axis == "y") return {0.0, sign, 0.0};
  if (axis == "z") return {0.0, 0.0, sign};
  throw OptionError("up", text, "must be x, y, z, -x, -y or -z");
}

}  // namespace osteon::simulation
