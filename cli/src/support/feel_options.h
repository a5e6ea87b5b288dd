// `--force-model`, `--rpm` and `--irrigation` of the drilling commands (docs/feel.md): the
// cutting resistance (the seed's, or calibrated to published thrust) and the drill's settings.
#pragma once

#include <optional>
#include <string>

#include "osteon/simulation/session.h"

namespace osteon::cli {

struct FeelCommandOptions {
  std::string forceModel = "seed";  // --force-model: seed or calibrated
  std::optional<double> rpm;        // --rpm (default 1000)
  bool irrigation = false;          // --irrigation
};

// Checked before any work: the model's name, the rpm's range, and the coupling: calibrated runs
// through the proxy (chosen when --coupling is not given; --coupling direct is refused).
// Returns the coupling the run takes.
simulation::CouplingMode checkFeel(const FeelCommandOptions& feel,
                                   const std::string& couplingOption,
                                   simulation::CouplingMode coupling);
// The session's model and settings.
void applyFeel(const FeelCommandOptions& feel, simulation::SessionOptions& options);
bool calibrated(const FeelCommandOptions& feel);

}  // namespace osteon::cli
