// `osteon drill MESH --path P`: one drilling run at 1 kHz in the deterministic mode (seed 4), or
// in real time with --threaded: forces.csv, summary.json and the drilled surface. With --device
// the run is driven by a device through the safety layer (drill_device.cpp).
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/runner.h"
#include "support/feel_options.h"
#include "support/igtl_serve.h"

namespace osteon::cli {

struct DrillCommandOptions {
  simulation::BoneSource bone;  // a mesh, `default` or a volume (then --path must be a CSV)
  int levels = 2;
  std::string path;  // portal-5, portal-7 or a CSV file
  std::string tool = "drill";
  std::string outDir = ".";
  bool threaded = false;  // the three-thread runtime in real time, not the deterministic mode
  bool json = false;
  std::string device;               // drive the run from a device instead of --path (devices.md)
  std::optional<double> durationS;  // a live device's run length
  std::string record;               // record the device's stream to this CSV
  bool allowEmpty = false;  // a path that never meets bone exits 0 (still "empty": true), not 1
  std::string coupling;     // proxy or direct; empty: direct for portal paths, else proxy
  IgtlCommandOptions igtl;  // serve the live run over OpenIGTLink (support/igtl_serve.h)
  FeelCommandOptions feel;  // --force-model, --rpm, --irrigation (support/feel_options.h)
  std::string audioOut;     // render the drill's sound to this WAV (support/audio_out.h)
};

// What a command that drills as `drill` does adds to its run (score): the session's options, a
// look at the session once it is open, every step, and the session once the run is done; and
// whether drill's own report is printed.
struct DrillExtension {
  std::function<simulation::OpenedBone(const simulation::BoneSource&)> openBone;  // else open()
  std::function<void(simulation::SessionOptions&)> sessionOptions;
  std::function<void(simulation::Session&)> opened;
  std::function<void(const simulation::ForceLogRow&)> onRow;
  std::function<void(std::size_t, const simulation::StepInput&, const simulation::StepOutput&)>
      afterStep;
  std::function<void(simulation::Session&)> done;  // before the surface is written
  bool printReport = true;
};

int runDrill(const DrillCommandOptions& options);
// The same run with `extension`'s additions (deterministic runs only).
int runDrill(const DrillCommandOptions& options, const DrillExtension& extension);
int runDrillWithDevice(const DrillCommandOptions& options);  // drill_device.cpp

}  // namespace osteon::cli
