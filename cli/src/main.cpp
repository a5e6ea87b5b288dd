// `osteon`: the command-line front end. This file only parses (CLI11 is slow to compile, so
// it lives here alone); commands.cpp does the work. Errors are one line on stderr.
#include "commands.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>

namespace {

using osteon::kExitBadInput;
using osteon::kExitInternal;
using osteon::kExitOk;

void addUnits(CLI::App& cmd, osteon::cli::BoneSource& source) {
  CLI::Option* u = cmd.add_option("--units", source.units,
                                  "Unit of the mesh file's coordinates: mm, cm, m or in")
                       ->default_str("mm");
  CLI::Option* s = cmd.add_option("--scale", source.scale,
                                  "Multiply coordinates by S to get millimetres");
  u->excludes(s);
}

// Commands that work on a grid take a mesh (voxelized at --voxel-size) or a saved grid.
void addGridInput(CLI::App& cmd, osteon::cli::BoneSource& source) {
  cmd.add_option("MESH", source.input,
                 "Mesh file, 'default', a GRID.nrrd written by osteon voxelize, or a volume "
                 "(.nrrd .nhdr .nii .nii.gz: label map or CT)")
      ->required();
  addUnits(cmd, source);
  cmd.add_option("--voxel-size", source.voxelSizeMm,
                 "Voxel edge in mm (required for a mesh; a grid has its own)");
}

// CLI11 reads "-1" into an unsigned as 2^64 - 1; a seed or label is refused rather than wrapped.
CLI::Validator nonNegativeInteger(const char* name) {
  return CLI::Validator(
      [](std::string& text) {
        const std::size_t first = text.find_first_not_of(" \t");
        return first != std::string::npos && text[first] == '-'
                   ? std::string("must be a non-negative integer, not ") + text
                   : std::string();
      },
      name);
}

// What a volume (NRRD or NIfTI) means, and whether an empty result is accepted.
void addVolumeMeaning(CLI::App& cmd, osteon::geometry::VolumeOptions& meaning) {
  cmd.add_option("--label", meaning.label,
                 "Label map volumes: the bone label, 0 .. 2^64-1 (default: every voxel but the background, "
                 "0 or else the most common value)")
      ->check(nonNegativeInteger("LABEL"));
  cmd.add_option("--iso", meaning.isoHu, "CT volumes: the bone threshold in HU (default 300)");
  cmd.add_flag("--allow-outside-data", meaning.allowOutsideData,
               "NRRD volumes: read a 'data file:' outside the header's folder (refused by default)");
}

void addAllowEmpty(CLI::App& cmd, bool& allowEmpty) {
  cmd.add_flag("--allow-empty", allowEmpty,
               "An empty result (no voxel inside, no triangles, no bone met) exits 0, not 1");
}

void addMesh(CLI::App& cmd, osteon::cli::BoneSource& source) {
  cmd.add_option("MESH", source.input, "Mesh file (.stl .obj .ply .off) or 'default' for the built-in humerus")
      ->required();
}

// CLI11 reports problems in paragraphs; we promise one line.
std::string oneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  // A write past `ulimit -f` then fails with EFBIG, told as one line naming the file, instead of
  // killing the process mid-file.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"osteon: crack-free multi-resolution bone drilling, from mesh to voxels to proof"};
  app.set_version_flag("--version", std::string("osteon ") + OSTEON_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);

  osteon::cli::InfoOptions info;
  CLI::App* infoCmd = app.add_subcommand("info", "Print a mesh's size, bounds, volume and topology");
  addMesh(*infoCmd, info.bone);
  addUnits(*infoCmd, info.bone);
  infoCmd->add_flag("--json", info.json, "Print one JSON object on stdout");

  osteon::cli::VoxelizeCommandOptions vox;
  CLI::App* voxCmd = app.add_subcommand("voxelize", "Voxelize a mesh by Embree ray projection (seed 3.2)");
  addMesh(*voxCmd, vox.bone);
  addUnits(*voxCmd, vox.bone);
  voxCmd->add_option("--voxel-size", vox.bone.voxelSizeMm, "Voxel edge length in mm")->required();
  voxCmd->add_flag("--robust", vox.robust,
                   "Cast along all three axes and take a majority vote (meshes with holes)");
  voxCmd->add_option("--rays", vox.raysPerAxis, "Rays per column along each side (R x R rays)")
      ->default_val(4);
  voxCmd->add_option("--cortical-mm", vox.corticalMm, "Cortical shell thickness in mm")
      ->default_val(2.0);
  voxCmd->add_option("--cortical-density", vox.corticalDensity, "Density d of cortical voxels")
      ->default_val(40);
  voxCmd->add_option("--cancellous-density", vox.cancellousDensity,
                     "Density d of cancellous voxels")
      ->default_val(15);
  voxCmd->add_option("--out", vox.out, "Write the grid as NRRD (fill; density beside it)");
  voxCmd->add_flag("--json", vox.json, "Print one JSON object on stdout");
  addAllowEmpty(*voxCmd, vox.allowEmpty);

  osteon::cli::HierarchyOptions dph;
  CLI::App* dphCmd = app.add_subcommand(
      "hierarchy", "Build the Dynamic Proximity Hierarchy over a voxelized mesh or grid (seed 3.3)");
  addGridInput(*dphCmd, dph.bone);
  dphCmd->add_option("--xi", dph.xi, "Expansion ratio (odd, 3..15)")->default_val(3);
  dphCmd->add_option("--seed", dph.seed, "Seed of the insertion order (0 .. 2^64-1)")
      ->default_val(1)
      ->check(nonNegativeInteger("SEED"));
  dphCmd->add_option("--svg", dph.svg, "Draw a z-slice of the hierarchy into this SVG file");
  dphCmd->add_option("--slice-z", dph.sliceZMm, "Height of the --svg slice in mm (default: middle)");
  dphCmd->add_flag("--json", dph.json, "Print one JSON object on stdout");
  addVolumeMeaning(*dphCmd, dph.bone.volume);
  addAllowEmpty(*dphCmd, dph.allowEmpty);

  osteon::cli::MeshCommandOptions meshOpt;
  CLI::App* meshCmd = app.add_subcommand(
      "mesh", "Extract the crack-free (or the seed's naive) surface of a voxelized mesh or grid");
  addGridInput(*meshCmd, meshOpt.bone);
  meshCmd->add_option("--method", meshOpt.method, "crackfree (shared vertices) or naive (seed's MC)")
      ->default_val("crackfree");
  meshCmd->add_option("--smooth", meshOpt.smooth, "Laplacian passes")->default_val(2);
  meshCmd->add_flag("--taubin", meshOpt.taubin, "Alternate shrink-free Taubin lambda/mu passes");
  meshCmd->add_option("--out", meshOpt.out, "Write the surface (.ply .obj .stl .off)");
  meshCmd->add_flag("--json", meshOpt.json, "Print one JSON object on stdout");
  addVolumeMeaning(*meshCmd, meshOpt.bone.volume);
  addAllowEmpty(*meshCmd, meshOpt.allowEmpty);

  osteon::cli::DrillCommandOptions drill;
  CLI::App* drillCmd = app.add_subcommand(
      "drill", "Drill a path into the bone at 1 kHz (deterministic): force log, summary, surface");
  addMesh(*drillCmd, drill.bone);
  drillCmd->get_option("MESH")->description(
      "Mesh file (.stl .obj .ply .off), 'default', or a volume (.nrrd .nhdr .nii .nii.gz)");
  addUnits(*drillCmd, drill.bone);
  drillCmd->add_option("--voxel-size", drill.bone.voxelSizeMm, "Base voxel edge in mm")->required();
  drillCmd->add_option("--levels", drill.levels,
                       "0: forces at the base voxel size; 1 or 2: refine near the tool (VS/2, VS/4)")
      ->default_val(2);
  CLI::Option* drillPath =
      drillCmd->add_option("--path", drill.path, "portal-5, portal-7 or PATH.csv (t,x,y,z,drill_on)");
  drillCmd->add_option("--tool", drill.tool, "drill, burr or shaver")->default_val("drill");
  drillCmd->add_option("--out-dir", drill.outDir, "Folder for forces.csv, summary.json, surface.ply")
      ->default_val(".");
  drillCmd->add_flag("--threaded", drill.threaded,
                     "Run the haptic, collision and visual threads in real time (not bit-identical)");
  drillCmd->add_flag("--json", drill.json, "Print the summary as JSON on stdout");
  drillCmd->add_option("--coupling", drill.coupling,
                       "proxy: bone stops the tool, a spring joins it to the command (default, but for "
                       "portal paths); direct: the tool is where the path puts it");
  addVolumeMeaning(*drillCmd, drill.bone.volume);
  addAllowEmpty(*drillCmd, drill.allowEmpty);
  drillCmd->add_option("--device", drill.device,
                       "Drive the run from a device instead of --path: mouse, spacemouse[:PATH], "
                       "serial:PORT[@BAUD], touch[:NAME], replay:LOG.csv, scripted:portal-5|portal-7|PATH.csv")
      ->excludes(drillPath);
  drillCmd->add_option("--duration", drill.durationS, "Seconds to run a live device (required for one)");
  drillCmd->add_option("--record", drill.record,
                       "Record the device's stream at 1 kHz to this CSV (t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on)");

  osteon::cli::ReplayCommandOptions replay;
  CLI::App* replayCmd = app.add_subcommand(
      "replay", "Replay a device recording through the safety layer into a deterministic session");
  replayCmd->add_option("LOG", replay.log, "Recording CSV: t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on")->required();
  addMesh(*replayCmd, replay.bone);
  addUnits(*replayCmd, replay.bone);
  replayCmd->add_option("--voxel-size", replay.bone.voxelSizeMm, "Base voxel edge in mm")->required();
  replayCmd->add_option("--levels", replay.levels,
                        "0: forces at the base voxel size; 1 or 2: refine near the tool (VS/2, VS/4)")
      ->default_val(2);
  replayCmd->add_option("--tool", replay.tool, "drill, burr or shaver")->default_val("drill");
  replayCmd->add_option("--out-dir", replay.outDir, "Folder for forces.csv, summary.json, surface.ply")
      ->default_val(".");
  replayCmd->add_flag("--json", replay.json, "Print the summary as JSON on stdout");
  addAllowEmpty(*replayCmd, replay.allowEmpty);
  replayCmd->add_option("--coupling", replay.coupling,
                        "proxy (default): bone stops the tool, a spring joins it to the recording; direct");

  CLI::App* devicesCmd = app.add_subcommand("devices", "List attached devices, or watch one's events");
  devicesCmd->require_subcommand(1);
  osteon::cli::DevicesListOptions devicesList;
  CLI::App* devicesListCmd =
      devicesCmd->add_subcommand("list", "3Dconnexion HID devices and USB serial ports attached now");
  devicesListCmd->add_flag("--json", devicesList.json, "Print one JSON object on stdout");
  osteon::cli::DevicesMonitorOptions monitor;
  CLI::App* monitorCmd = devicesCmd->add_subcommand("monitor", "Print a device's events, one per line");
  monitorCmd->add_option("DEVICE", monitor.device, "Device name, e.g. serial:/dev/ttyACM0 or spacemouse")->required();
  monitorCmd->add_option("--count", monitor.count, "Exit 0 after this many events");
  monitorCmd->add_option("--duration", monitor.durationS, "Exit 0 after this many seconds");
  monitorCmd->add_flag("--json", monitor.json, "One JSON object per event");

  osteon::cli::CheckCommandOptions check;
  CLI::App* checkCmd = app.add_subcommand(
      "check", "Prove a surface crack-free: exact checks (CGAL), pixel crack metric, accuracy");
  addMesh(*checkCmd, check.bone);
  addUnits(*checkCmd, check.bone);
  checkCmd->add_option("--reference", check.reference,
                       "Mesh the surface came from (same units): Hausdorff distance, volume difference");
  checkCmd->add_option("--cracks", check.cracks, "Pixels per side of each of the six crack views")
      ->default_val(512);
  checkCmd->add_option("--images", check.images, "Write the six crack views as PNG into this folder");
  checkCmd->add_flag("--json", check.json, "Print one JSON object on stdout");

  osteon::cli::ValidateCommandOptions validate;
  CLI::App* validateCmd = app.add_subcommand(
      "validate", "The nightly run: every guarantee on models x voxel sizes x methods x modes; report");
  validateCmd->add_option("--models", validate.models,
                          "Comma-separated meshes ('default' for the built-in) or volumes (.nrrd .nhdr .nii .nii.gz: "
                          "at their own voxel size, every non-background label or 300 HU)")
      ->default_val("default");
  addUnits(*validateCmd, validate.source);
  validateCmd->add_option("--voxel-sizes", validate.voxelSizes, "Comma-separated voxel sizes in mm")
      ->default_val("1.2,0.9,0.72,0.54");
  validateCmd->add_flag("--quick", validate.quick,
                        "1.2 mm only (unless --voxel-sizes is given), coarser checks: about a minute");
  validateCmd->add_option("--out-dir", validate.outDir, "Folder for report.html, report.json, the log, images")
      ->default_val("validation-report");
  validateCmd->add_option("--compare", validate.compare, "A previous report.json: mark regressions");
  validateCmd->add_flag("--allow-outside-data", validate.source.volume.allowOutsideData,
                        "NRRD volumes in --models: read a 'data file:' outside the header's folder");
  validateCmd->add_option("--shard", validate.shard,
                          "K/N: run only the K-th (0-based, 0..N-1) of N disjoint parts of the cases, balanced by "
                          "estimated cost; merge the shards' folders with --merge");
  validateCmd->add_option("--merge", validate.merge,
                          "Shard folders (each with the report.json of one --shard K/N run): merge them into one "
                          "report in --out-dir instead of running");

  osteon::cli::ExperimentCommandOptions experiment;
  CLI::App* experimentCmd = app.add_subcommand(
      "experiment", "Rerun a paper experiment: 'seed' is section 4 (static vs dynamic force plots)");
  experimentCmd->add_option("NAME", experiment.name, "Experiment: seed")->required();
  experimentCmd->add_option("--mesh", experiment.bone.input, "Humerus mesh, or 'default'")->default_val("default");
  addUnits(*experimentCmd, experiment.bone);
  experimentCmd->add_option("--out-dir", experiment.outDir, "Folder for plots, table and logs")
      ->default_val("experiment-seed");
  experimentCmd->add_flag("--json", experiment.json, "Print the table as JSON on stdout");

  osteon::cli::ModelOptions model;
  CLI::App* modelCmd = app.add_subcommand(
      "model", "Build the built-in proximal humerus (what 'default' means) and optionally write it");
  modelCmd->add_option("--out", model.out, "Mesh file to write (.stl .obj .ply .off)");
  modelCmd->add_flag("--json", model.json, "Print one JSON object on stdout");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    std::cout << "osteon " << OSTEON_VERSION << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    // Name an unknown command rather than CLI11's "a subcommand is required".
    const auto known = [&](const std::string& name) {
      for (const CLI::App* sub : {infoCmd, voxCmd, modelCmd, dphCmd, meshCmd, drillCmd, experimentCmd, checkCmd, validateCmd,
                                  replayCmd, devicesCmd}) {
        if (sub->get_name() == name) return true;
      }
      return false;
    };
    if (argc > 1 && argv[1][0] != '-' && !known(argv[1])) {
      std::cerr << "osteon: error: " << argv[1]
                << ": unknown command (expected info, voxelize, hierarchy, mesh, check, validate, drill, "
                   "replay, devices, experiment or model; "
                   "see osteon "
                   "--help)\n";
      return kExitBadInput;
    }
    std::cerr << "osteon: error: " << oneLine(e.what()) << " (see osteon --help)\n";
    return kExitBadInput;
  }

  validate.voxelSizesGiven = validateCmd->count("--voxel-sizes") > 0;
  for (const char* name : {"--models", "--voxel-sizes", "--quick", "--shard", "--units", "--scale", "--allow-outside-data"}) {
    if (validateCmd->count(name) > 0) validate.runOptionsGiven.push_back(name);
  }
  try {
    if (*infoCmd) return osteon::cli::runInfo(info);
    if (*voxCmd) return osteon::cli::runVoxelize(vox);
    if (*modelCmd) return osteon::cli::runModel(model);
    if (*dphCmd) return osteon::cli::runHierarchy(dph);
    if (*meshCmd) return osteon::cli::runMesh(meshOpt);
    if (*drillCmd) return osteon::cli::runDrill(drill);
    if (*experimentCmd) return osteon::cli::runExperiment(experiment);
    if (*checkCmd) return osteon::cli::runCheck(check);
    if (*validateCmd) return osteon::cli::runValidate(validate);
    if (*replayCmd) return osteon::cli::runReplay(replay);
    if (*devicesListCmd) return osteon::cli::runDevicesList(devicesList);
    if (*monitorCmd) return osteon::cli::runDevicesMonitor(monitor);
  } catch (const osteon::Interrupted& e) {
    // The run's folder keeps its previous outputs (output_dir.h): nothing of this run is in it.
    std::cerr << "osteon: " << e.what() << ": the run stopped; its output folder keeps what it held before\n";
    return e.exitCode();
  } catch (const osteon::InputError& e) {
    std::cerr << "osteon: error: " << oneLine(osteon::simulation::commandLineMessage(e)) << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "osteon: error: out of memory: the input needs more memory than this machine "
                 "has (a larger --voxel-size needs less)\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "osteon: internal error: " << oneLine(e.what()) << "\n";
    return kExitInternal;
  }
  return kExitBadInput;
}
