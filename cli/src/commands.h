// The commands behind `osteon`, free of CLI11 so that parsing and work compile apart.
// Each returns the process exit code: 0 success, 1 a check failed, 2 bad input or usage.
#pragma once

#include "osteon/core/error.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace osteon::cli {


// How a mesh argument's coordinates become millimetres: --units or --scale, never both.
struct MeshUnits {
  std::string units = "mm";
  std::optional<double> scale;
};

// What a volume (NRRD or NIfTI that is not osteon's own grid) means (volume_io.h).
struct VolumeMeaning {
  std::optional<std::uint64_t> label;  // label maps: the bone label (default: all but the background)
  std::optional<double> isoHu;         // CTs: the bone threshold in HU (default 300)
  bool allowOutsideData = false;       // NRRD: read a `data file:` outside the header's folder
};

struct InfoOptions {
  std::string mesh;
  MeshUnits units;
  bool json = false;
};

struct VoxelizeCommandOptions {
  std::string mesh;
  MeshUnits units;
  double voxelSizeMm = 0.0;
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
  std::string input;  // mesh, `default`, or GRID.nrrd
  MeshUnits units;
  std::optional<double> voxelSizeMm;
  int xi = 3;
  std::uint64_t seed = 1;
  std::string svg;     // a slice of the hierarchy as SVG, empty for none
  std::optional<double> sliceZMm;
  bool json = false;
  VolumeMeaning volume;
  bool allowEmpty = false;
};

struct MeshCommandOptions {
  std::string input;  // mesh, `default`, or GRID.nrrd
  MeshUnits units;
  std::optional<double> voxelSizeMm;
  std::string method = "crackfree";
  int smooth = 2;
  bool taubin = false;
  std::string out;
  bool json = false;
  VolumeMeaning volume;
  bool allowEmpty = false;
};

struct ModelOptions {
  std::string out;  // mesh file to write, empty for none
  bool json = false;
};

struct DrillCommandOptions {
  std::string mesh;
  MeshUnits units;
  double voxelSizeMm = 0.0;
  int levels = 2;
  std::string path;          // portal-5, portal-7 or a CSV file
  std::string tool = "drill";
  std::string outDir = ".";
  bool threaded = false;     // the three-thread runtime in real time, not the deterministic mode
  bool json = false;
  std::string device;        // drive the run from a device instead of --path (devices.md)
  std::optional<double> durationS;  // a live device's run length
  std::string record;        // record the device's stream to this CSV
  VolumeMeaning volume;      // when `mesh` is a volume (then --path must be a CSV)
  bool allowEmpty = false;   // a path that never meets bone exits 0 (still "empty": true), not 1
  std::string coupling;      // proxy or direct; empty: direct for portal paths, else proxy
};

struct ReplayCommandOptions {
  std::string log;           // a recording: t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on
  std::string mesh;
  MeshUnits units;
  double voxelSizeMm = 0.0;
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
  std::string mesh;
  MeshUnits units;
  std::string reference;  // empty: no accuracy
  int cracks = 512;       // pixels per side of each crack view
  std::string images;     // folder for the six crack views, empty for none
  bool json = false;
};

struct ValidateCommandOptions {
  std::string models = "default";      // comma-separated: default or mesh paths
  MeshUnits units;
  std::string voxelSizes = "1.2,0.9,0.72,0.54";
  bool voxelSizesGiven = false;        // --voxel-sizes on the command line (overrides --quick's)
  bool quick = false;
  std::string outDir = "validation-report";
  std::string compare;                 // a previous report.json
  std::string shard;                   // "K/N": run the K-th (0-based) of N shards; empty: all
  bool allowOutsideData = false;       // NRRD volumes in --models: a data file may lie outside its header's folder
  std::vector<std::string> merge;      // shard out-dirs to merge into --out-dir instead of a run
  std::vector<std::string> runOptionsGiven;  // options of a run given on the command line (--models ...)
};

struct ExperimentCommandOptions {
  std::string name;               // "seed"
  std::string mesh = "default";
  MeshUnits units;
  std::string outDir = "experiment-seed";
  bool json = false;
};

// Millimetres per file unit from --units or --scale; throws InputError for bad values.
double scaleToMm(const MeshUnits& units);

// The file a mesh argument reads: itself, or nothing for `default`.
std::string inputFile(const std::string& meshArgument);

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
