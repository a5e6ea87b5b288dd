// `osteon drill MESH --path P`: one drilling run at 1 kHz in the deterministic mode (seed 4), or
// in real time with --threaded: forces.csv, summary.json and the drilled surface. With --device
// the run is driven by a device through the safety layer (drill_device.cpp).
#pragma once

#include <optional>
#include <string>

#include "osteon/simulation/bone_source.h"

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
};

int runDrill(const DrillCommandOptions& options);
int runDrillWithDevice(const DrillCommandOptions& options);  // drill_device.cpp

}  // namespace osteon::cli
