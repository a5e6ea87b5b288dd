// `--igtl PORT` of live runs (drill --threaded, drill --device): the run served over
// OpenIGTLink while it runs (osteon_igtl, docs/slicer.md), fed from the threaded runtime's
// visual side, never from its 1 kHz loops.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"

namespace osteon::cli {

struct IgtlCommandOptions {
  std::optional<int> port;              // --igtl: serve on this TCP port
  std::string bind = "127.0.0.1";       // --igtl-bind
  std::string content = "fill";         // --igtl-content: fill or density
  std::optional<double> surfaceEveryS;  // --igtl-surface-every: BoneSurface every S seconds
};

// Refused before the work: an --igtl-* option without --igtl, bad values, or a run that is not
// live (`live`: the threaded runtime runs it).
void checkIgtlOptions(const IgtlCommandOptions& options, bool live);

// A server for the run when --igtl is given, nothing otherwise. attach() feeds it from the
// runtime's visual thread; finish() stops it (letting the queues drain for a moment) and gives
// the "igtl" object of the run's JSON: clients, messages and bytes sent, drops.
class IgtlServe {
 public:
  IgtlServe(const IgtlCommandOptions& options, const simulation::Session& session);
  ~IgtlServe();
  void attach(simulation::RuntimeOptions& runtime);
  nlohmann::json finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace osteon::cli
