#include "support/feel_options.h"

#include "osteon/core/error.h"
#include "osteon/simulation/cutting.h"

namespace osteon::cli {

namespace sim = osteon::simulation;

bool calibrated(const FeelCommandOptions& feel) {
  return sim::parseForceModelKind(feel.forceModel) == sim::ForceModelKind::Calibrated;
}

sim::CouplingMode checkFeel(const FeelCommandOptions& feel, const std::string& couplingOption,
                            sim::CouplingMode coupling) {
  if (feel.rpm) sim::validateRpm(*feel.rpm);
  if (!calibrated(feel)) return coupling;
  if (couplingOption == "direct") {
    throw InputError(
        "--force-model calibrated: needs the proxy (its feed renders the bone's resistance); "
        "drop --coupling direct");
  }
  return sim::CouplingMode::Proxy;
}

void applyFeel(const FeelCommandOptions& feel, sim::SessionOptions& options) {
  options.forceModel = sim::parseForceModelKind(feel.forceModel);
  if (feel.rpm) options.settings.rpm = *feel.rpm;
  options.settings.irrigation = feel.irrigation;
}

}  // namespace osteon::cli
