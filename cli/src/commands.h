// The commands behind `osteon`, free of CLI11 so that parsing and work compile apart.
// Each returns the process exit code: 0 success, 1 a check failed, 2 bad input or usage.
#pragma once

#include "osteon/core/error.h"
#include "osteon/simulation/bone_source.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace osteon::cli {


// Every command's bone (its input, units or scale, voxel size, volume options) is a
// simulation::BoneSource, opened by BoneModel::open or loadBoneMesh.
using simulation::BoneSource;

struct InfoOptions {
  BoneSource bone;  // a mesh or `default`
  bool json = false;
};

struct VoxelizeCommandOptions {
  BoneSource bone;  // a mesh or `default`, its units and voxel size
  bool robust = false;
  int raysPerAxis = 4;
  double corticalMm = 2.0;
  int corticalDensity = 40;
  int cancellousDensity = 15;
  std::string out;  // GRID.nrrd, empty for none
  bool json = false;
  bool allowEmpty = false;  // an empty grid exits 0 (still "empty": true), not 1
};

struct HierarchyOptions {
  BoneSource bone;  // a mesh, `default`, a GRID.nrrd or another volume
  int xi = 3;
  std::uint64_t seed = 1;
  std::string svg;     // a slice of the hierarchy as SVG, empty for none
  std::optional<double> sliceZMm;
  bool json = false;
  bool allowEmpty = false;
};

struct MeshCommandOptions {
  BoneSource bone;  // a mesh, `default`, a GRID.nrrd or another volume
  std::string method = "crackfree";
  int smooth = 2;
  bool taubin = false;
  std::string out;
  bool json = false;
  bool allowEmpty = false;
};

struct ModelOptions {
  std::string out;  // mesh file to write, empty for none
  bool json = false;
};

struct DrillCommandOptions {
  BoneSource bone;           // a mesh, `default` or a volume (then --path must be a CSV)
  int levels = 2;
  std::string path;          // portal-5, portal-7 or a CSV file
  std::string tool = "drill";
  std::string outDir = ".";
  bool threaded = false;     // the three-thread runtime in real time, not the deterministic mode
  bool json = false;
  std::string device;        // drive the run from a device instead of --path (devices.md)
  std::optional<double> durationS;  // a live device's run length
  std::string record;        // record the device's stream to this CSV
  bool allowEmpty = false;   // a path that never meets bone exits 0 (still "empty": true), not 1
  std::string coupling;      // proxy or direct; empty: direct for portal paths, else proxy
};

struct ReplayCommandOptions {
  std::string log;           // a recording: t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on
  BoneSource bone;           // a mesh or `default`
  int levels = 2;
  std::string tool = "drill";
  std::string outDir = ".";
  bool json = false;
  bool allowEmpty = false;   // a recording that never meets bone exits 0 (still "empty": true), not 1
  std::string coupling;      // proxy (the default) or direct
};

struct DevicesListOptions {
  bool json = false;
};

struct DevicesMonitorOptions {
  std::string device;
  std::optional<long long> count;    // stop after this many events
  std::optional<double> durationS;   // stop after this long
  bool json = false;
};

struct CheckCommandOptions {
  BoneSource bone;        // the surface to check; its units are the reference's too
  std::string reference;  // empty: no accuracy
  int cracks = 512;       // pixels per side of each crack view
  std::string images;     // folder for the six crack views, empty for none
  bool json = false;
};

struct ValidateCommandOptions {
  std::string models = "default";      // comma-separated: default or mesh paths
  BoneSource source;                   // each model's units or scale and volume options (input: each of models)
  std::string voxelSizes = "1.2,0.9,0.72,0.54";
  bool voxelSizesGiven = false;        // --voxel-sizes on the command line (overrides --quick's)
  bool quick = false;
  std::string outDir = "validation-report";
  std::string compare;                 // a previous report.json
  std::string shard;                   // "K/N": run the K-th (0-based) of N shards; empty: all
  std::vector<std::string> merge;      // shard out-dirs to merge into --out-dir instead of a run
  std::vector<std::string> runOptionsGiven;  // options of a run given on the command line (--models ...)
};

struct ExperimentCommandOptions {
  std::string name;               // "seed"
  BoneSource bone;                // the humerus, `default` by default
  std::string outDir = "experiment-seed";
  bool json = false;
};

// Refuses (InputError) any existing input inside `folder`, which a command fills with files of
// its own naming (run logs, images).
void refuseInputsInside(const std::string& folder, const std::vector<std::string>& inputs);

// An empty result (no voxel inside, no triangles, a path that never meets bone): one line on
// stderr naming the command, the input and the reason; kExitCheckFailed unless allowEmpty.
int emptyExit(const char* command, const std::string& input, const std::string& reason, bool allowEmpty);

int runInfo(const InfoOptions& options);
int runVoxelize(const VoxelizeCommandOptions& options);
int runModel(const ModelOptions& options);
int runHierarchy(const HierarchyOptions& options);
int runMesh(const MeshCommandOptions& options);
int runDrill(const DrillCommandOptions& options);  // drill.cpp
int runExperiment(const ExperimentCommandOptions& options);  // experiment.cpp
int runCheck(const CheckCommandOptions& options);  // check.cpp
int runValidate(const ValidateCommandOptions& options);  // validate.cpp
int runReplay(const ReplayCommandOptions& options);  // replay.cpp
int runDrillWithDevice(const DrillCommandOptions& options);  // replay.cpp: drill --device
int runDevicesList(const DevicesListOptions& options);  // devices.cpp
int runDevicesMonitor(const DevicesMonitorOptions& options);  // devices.cpp

}  // namespace osteon::cli
