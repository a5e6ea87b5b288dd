// Each subcommand's options as CLI11 options (CLI11 is slow to compile: it lives here and in
// main.cpp alone), and the table of subcommands.
#include "command_table.h"

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands/check.h"
#include "commands/devices.h"
#include "commands/drill.h"
#include "commands/exercise.h"
#include "commands/experiment.h"
#include "commands/hierarchy.h"
#include "commands/info.h"
#include "commands/mesh.h"
#include "commands/model.h"
#include "commands/replay.h"
#include "commands/score.h"
#include "commands/validate.h"
#include "commands/voxelize.h"
#include "osteon/core/option_error.h"
#include "osteon/simulation/bone_source.h"
namespace osteon::cli {

namespace {

using simulation::BoneSource;

void addUnits(CLI::App& cmd, BoneSource& source) {
  CLI::Option* u = cmd.add_option("--units", source.units,
                                  "Unit of the mesh file's coordinates: mm, cm, m or in")
                       ->default_str("mm");
  CLI::Option* s =
      cmd.add_option("--scale", source.scale, "Multiply coordinates by S to get millimetres");
  u->excludes(s);
}

void addMesh(CLI::App& cmd, BoneSource& source) {
  cmd.add_option("MESH", source.input,
                 "Mesh file (.stl .obj .ply .off) or 'default' for the built-in humerus")
      ->required();
}

// Commands that drill take a mesh or a volume.
void describeBoneInput(CLI::App& cmd) {
  cmd.get_option("MESH")->description(std::string("Mesh file (.stl .obj .ply .off), 'default', or "
                                                  "a volume (") +
                                      simulation::kVolumeFormsText + ")");
}

// Commands that work on a grid take a mesh (voxelized at --voxel-size) or a saved grid.
void addGridInput(CLI::App& cmd, BoneSource& source) {
  cmd.add_option("MESH", source.input,
                 std::string("Mesh file, 'default', a GRID.nrrd written by osteon voxelize, or a "
                             "volume (") +
                     simulation::kVolumeFormsText + ": label map, CT or scalar volume)")
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
void addVolumeMeaning(CLI::App& cmd, geometry::VolumeOptions& meaning) {
  cmd.add_option(
         "--label", meaning.label,
         "Label map volumes: the bone label, 0 .. 2^64-1 (default: every voxel but the background, "
         "0 or else the most common value)")
      ->check(nonNegativeInteger("LABEL"));
  cmd.add_option("--iso", meaning.isoValue,
                 "CT volumes: the bone threshold in HU (default 300); any other volume (micro-CT, "
                 "probability map): bone above this value, in the volume's own units");
  cmd.add_option_function<std::string>(
      "--crop",
      [&meaning](const std::string& text) {
        try {
          meaning.cropMm = simulation::parseCropMm(text);
        } catch (const OptionError& e) {
          throw CLI::ValidationError(e.renamed("--crop"));
        }
      },
      "Volumes: load only X0:X1,Y0:Y1,Z0:Z1 (LPS mm, voxel centres inside)");
  cmd.add_option("--crop-to-label", meaning.cropToLabel,
                 "Label map volumes: load only the box of this label, grown by --crop-margin")
      ->check(nonNegativeInteger("LABEL"));
  cmd.add_option("--crop-margin", meaning.cropMarginMm,
                 "mm added on every side of --crop-to-label's box (default 10)");
  cmd.add_flag(
      "--allow-outside-data", meaning.allowOutsideData,
      "NRRD and MetaImage volumes: read a data file outside the header's folder (refused by "
      "default)");
  cmd.add_option("--series", meaning.series,
                 "DICOM folders: the Series Instance UID to read (default: the series with most "
                 "slices)");
}

void addAllowEmpty(CLI::App& cmd, bool& allowEmpty) {
  cmd.add_flag("--allow-empty", allowEmpty,
               "An empty result (no voxel inside, no triangles, no bone met) exits 0, not 1");
}

void addJson(CLI::App& cmd, bool& json, const char* help = "Print one JSON object on stdout") {
  cmd.add_flag("--json", json, help);
}

// drill and replay: the drilling run's own options.
void addRunOptions(CLI::App& cmd, int& levels, std::string& tool, std::string& outDir) {
  cmd.add_option("--levels", levels,
                 "0: forces at the base voxel size; 1 or 2: refine near the tool (VS/2, VS/4)")
      ->default_val(2);
  cmd.add_option("--tool", tool, "drill, burr or shaver")->default_val("drill");
  cmd.add_option("--out-dir", outDir, "Folder for forces.csv, summary.json, surface.ply")
      ->default_val(".");
}

// The cutting resistance and the drill's settings (docs/feel.md).
void addFeel(CLI::App& cmd, FeelCommandOptions& o) {
  cmd.add_option("--force-model", o.forceModel,
                 "seed (the paper's eq. 2, default) or calibrated (thrust fitted to published "
                 "drilling data: rpm, feed, density)");
  cmd.add_option("--rpm", o.rpm, "The drill's speed, revolutions per minute (default 1000)");
  cmd.add_flag("--irrigation", o.irrigation, "Saline irrigation on (cools the bone)");
}

// A live run served over OpenIGTLink (docs/slicer.md).
void addAudioOut(CLI::App& cmd, std::string& audioOut) {
  cmd.add_option("--audio-out", audioOut,
                 "Render the drill's sound to this 16-bit PCM .wav (docs/feel.md, Sound)");
}

void addIgtl(CLI::App& cmd, IgtlCommandOptions& o) {
  cmd.add_option("--igtl", o.port,
                 "Serve the live run over OpenIGTLink on this TCP port (3D Slicer: 18944)");
  cmd.add_option("--igtl-bind", o.bind, "The address --igtl listens on (default 127.0.0.1)");
  cmd.add_option("--igtl-content", o.content, "The IMAGE Bone's voxels: fill (uint8) or density");
  cmd.add_option("--igtl-surface-every", o.surfaceEveryS,
                 "Send the surface (POLYDATA BoneSurface) every S seconds, not only on request");
}

void addUp(CLI::App& cmd, std::string& up) {
  cmd.add_option("--up", up,
                 "The bone's up axis, from the shaft to the humeral head: x, y, z, -x, -y or -z "
                 "(default: found from the bone)");
}

void addInfo(CLI::App& cmd, InfoOptions& o) {
  addMesh(cmd, o.bone);
  cmd.get_option("MESH")->description(
      std::string("Mesh file (.stl .obj .ply .off), 'default', or a volume (") +
      simulation::kVolumeFormsText + "; a DICOM folder lists its series)");
  addUnits(cmd, o.bone);
  addVolumeMeaning(cmd, o.bone.volume);
  addJson(cmd, o.json);
}

void addVoxelize(CLI::App& cmd, VoxelizeCommandOptions& o) {
  addMesh(cmd, o.bone);
  describeBoneInput(cmd);
  addUnits(cmd, o.bone);
  cmd.add_option("--voxel-size", o.bone.voxelSizeMm, "Voxel edge length in mm")->required();
  cmd.add_flag("--robust", o.robust,
               "Cast along all three axes and take a majority vote (meshes with holes)");
  cmd.add_option("--rays", o.raysPerAxis, "Rays per column along each side (R x R rays)")
      ->default_val(4);
  cmd.add_option("--cortical-mm", o.corticalMm, "Cortical shell thickness in mm")->default_val(2.0);
  cmd.add_option("--cortical-density", o.corticalDensity, "Density d of cortical voxels")
      ->default_val(40);
  cmd.add_option("--cancellous-density", o.cancellousDensity, "Density d of cancellous voxels")
      ->default_val(15);
  cmd.add_option("--out", o.out, "Write the grid as NRRD (fill; density beside it)");
  addJson(cmd, o.json);
  addAllowEmpty(cmd, o.allowEmpty);
}

void addHierarchy(CLI::App& cmd, HierarchyOptions& o) {
  addGridInput(cmd, o.bone);
  cmd.add_option("--xi", o.xi, "Expansion ratio (odd, 3..15)")->default_val(3);
  cmd.add_option("--seed", o.seed, "Seed of the insertion order (0 .. 2^64-1)")
      ->default_val(1)
      ->check(nonNegativeInteger("SEED"));
  cmd.add_option("--svg", o.svg, "Draw a z-slice of the hierarchy into this SVG file");
  cmd.add_option("--slice-z", o.sliceZMm, "Height of the --svg slice in mm (default: middle)");
  addJson(cmd, o.json);
  addVolumeMeaning(cmd, o.bone.volume);
  addAllowEmpty(cmd, o.allowEmpty);
}

void addMeshCommand(CLI::App& cmd, MeshCommandOptions& o) {
  addGridInput(cmd, o.bone);
  cmd.add_option("--method", o.method, "crackfree (shared vertices) or naive (seed's MC)")
      ->default_val("crackfree");
  cmd.add_option("--smooth", o.smooth, "Laplacian passes")->default_val(2);
  cmd.add_flag("--taubin", o.taubin, "Alternate shrink-free Taubin lambda/mu passes");
  cmd.add_option("--out", o.out, "Write the surface (.ply .obj .stl .off)");
  addJson(cmd, o.json);
  addVolumeMeaning(cmd, o.bone.volume);
  addAllowEmpty(cmd, o.allowEmpty);
}

void addDrill(CLI::App& cmd, DrillCommandOptions& o) {
  addMesh(cmd, o.bone);
  describeBoneInput(cmd);
  addUnits(cmd, o.bone);
  cmd.add_option("--voxel-size", o.bone.voxelSizeMm,
                 "Base voxel edge in mm (required for a mesh; a volume's default: its finest "
                 "spacing)");
  cmd.add_option("--levels", o.levels,
                 "0: forces at the base voxel size; 1 or 2: refine near the tool (VS/2, VS/4)")
      ->default_val(2);
  CLI::Option* path =
      cmd.add_option("--path", o.path, "portal-5, portal-7 or PATH.csv (t,x,y,z,drill_on)");
  cmd.add_option("--tool", o.tool, "drill, burr or shaver")->default_val("drill");
  cmd.add_option("--out-dir", o.outDir, "Folder for forces.csv, summary.json, surface.ply")
      ->default_val(".");
  cmd.add_flag("--threaded", o.threaded,
               "Run the haptic, collision and visual threads in real time (not bit-identical)");
  addJson(cmd, o.json, "Print the summary as JSON on stdout");
  cmd.add_option("--coupling", o.coupling,
                 "proxy: bone stops the tool, a spring joins it to the command (default, but for "
                 "portal paths); direct: the tool is where the path puts it");
  addVolumeMeaning(cmd, o.bone.volume);
  addAllowEmpty(cmd, o.allowEmpty);
  cmd.add_option(
         "--device", o.device,
         "Drive the run from a device instead of --path: mouse, spacemouse[:PATH], "
         "serial:PORT[@BAUD], touch[:NAME], replay:LOG.csv, scripted:portal-5|portal-7|PATH.csv")
      ->excludes(path);
  cmd.add_option("--duration", o.durationS, "Seconds to run a live device (required for one)");
  addUp(cmd, o.bone.up);
  cmd.add_option("--record", o.record,
                 "Record the device's stream at 1 kHz to this CSV "
                 "(t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on,rpm,irrigation)");
  addIgtl(cmd, o.igtl);
  addFeel(cmd, o.feel);
  addAudioOut(cmd, o.audioOut);
}

void addReplay(CLI::App& cmd, ReplayCommandOptions& o) {
  cmd.add_option("LOG", o.log,
                 "Recording CSV: t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on[,rpm,irrigation]")
      ->required();
  addMesh(cmd, o.bone);
  describeBoneInput(cmd);
  addUnits(cmd, o.bone);
  cmd.add_option("--voxel-size", o.bone.voxelSizeMm,
                 "Base voxel edge in mm (required for a mesh; a volume's default: its finest "
                 "spacing)");
  addRunOptions(cmd, o.levels, o.tool, o.outDir);
  addJson(cmd, o.json, "Print the summary as JSON on stdout");
  addVolumeMeaning(cmd, o.bone.volume);
  addAllowEmpty(cmd, o.allowEmpty);
  cmd.add_option(
      "--coupling", o.coupling,
      "proxy (default): bone stops the tool, a spring joins it to the recording; direct");
  addIgtl(cmd, o.igtl);  // replays in real time (threaded), served while it runs
  addFeel(cmd, o.feel);
  addAudioOut(cmd, o.audioOut);
}

void addDevices(CLI::App& cmd, DevicesCommandOptions& o) {
  cmd.require_subcommand(1);
  CLI::App* list =
      cmd.add_subcommand("list", "3Dconnexion HID devices and USB serial ports attached now");
  addJson(*list, o.list.json);
  list->callback([&o] { o.which = "list"; });
  CLI::App* monitor = cmd.add_subcommand("monitor", "Print a device's events, one per line");
  monitor
      ->add_option("DEVICE", o.monitor.device,
                   "Device name, e.g. serial:/dev/ttyACM0 or spacemouse")
      ->required();
  monitor->add_option("--count", o.monitor.count, "Exit 0 after this many events");
  monitor->add_option("--duration", o.monitor.durationS, "Exit 0 after this many seconds");
  addJson(*monitor, o.monitor.json, "One JSON object per event");
  monitor->callback([&o] { o.which = "monitor"; });
}

void addCheck(CLI::App& cmd, CheckCommandOptions& o) {
  addMesh(cmd, o.bone);
  addUnits(cmd, o.bone);
  cmd.add_option("--reference", o.reference,
                 "Mesh the surface came from (same units): Hausdorff distance, volume difference");
  cmd.add_option("--cracks", o.cracks, "Pixels per side of each of the six crack views")
      ->default_val(512);
  cmd.add_option("--images", o.images, "Write the six crack views as PNG into this folder");
  addJson(cmd, o.json);
}

void addValidate(CLI::App& cmd, ValidateCommandOptions& o) {
  cmd.add_option("--models", o.models,
                 std::string("Comma-separated meshes ('default' for the built-in) or volumes (") +
                     simulation::kVolumeFormsText +
                     ": at their own voxel size, every non-background label or 300 HU)")
      ->default_val("default");
  addUnits(cmd, o.source);
  cmd.add_option("--voxel-sizes", o.voxelSizes, "Comma-separated voxel sizes in mm")
      ->default_val("1.2,0.9,0.72,0.54");
  cmd.add_flag("--quick", o.quick,
               "1.2 mm only (unless --voxel-sizes is given), coarser checks: about a minute");
  cmd.add_option("--out-dir", o.outDir, "Folder for report.html, report.json, the log, images")
      ->default_val("validation-report");
  cmd.add_option("--compare", o.compare, "A previous report.json: mark regressions");
  cmd.add_flag(
      "--allow-outside-data", o.source.volume.allowOutsideData,
      "NRRD and MetaImage volumes in --models: read a data file outside the header's folder");
  cmd.add_option(
      "--shard", o.shard,
      "K/N: run only the K-th (0-based, 0..N-1) of N disjoint parts of the cases, balanced by "
      "estimated cost; merge the shards' folders with --merge");
  cmd.add_option(
      "--merge", o.merge,
      "Shard folders (each with the report.json of one --shard K/N run): merge them into one "
      "report in --out-dir instead of running");
  // Which options of a run were given (a merge refuses them; --voxel-sizes overrides --quick's).
  cmd.callback([&cmd, &o] {
    o.voxelSizesGiven = cmd.count("--voxel-sizes") > 0;
    for (const char* name : {"--models", "--voxel-sizes", "--quick", "--shard", "--units",
                             "--scale", "--allow-outside-data"}) {
      if (cmd.count(name) > 0) o.runOptionsGiven.push_back(name);
    }
  });
}

void addExperiment(CLI::App& cmd, ExperimentCommandOptions& o) {
  cmd.add_option("NAME", o.name,
                 "Experiment: seed (the paper's section 4), thrust (drilling thrust against "
                 "published data) or heat (bone temperature against Augustin et al. 2008)")
      ->required();
  cmd.add_option("--mesh", o.bone.input,
                 "Humerus mesh, 'default', or a volume (its surface at its own voxels)")
      ->default_val("default");
  addUnits(cmd, o.bone);
  addVolumeMeaning(cmd, o.bone.volume);
  cmd.add_option("--out-dir", o.outDir, "Folder for plots, table and logs (experiment-NAME)");
  addUp(cmd, o.bone.up);
  addJson(cmd, o.json, "Print the table as JSON on stdout");
}

void addExercise(CLI::App& cmd, ExerciseCommandOptions& o) {
  cmd.require_subcommand(1);
  CLI::App* list = cmd.add_subcommand("list", "The built-in exercises");
  addJson(*list, o.json);
  list->callback([&o] { o.which = "list"; });
  CLI::App* show = cmd.add_subcommand("show", "An exercise whole: instructions and its JSON");
  show->add_option("NAME", o.exercise, "anchor-5, anchor-7 or an exercise file (.json)")
      ->required();
  addJson(*show, o.json);
  show->callback([&o] { o.which = "show"; });
  CLI::App* plan =
      cmd.add_subcommand("plan", "Resolve an exercise on its bone; write the ideal path CSV");
  plan->add_option("NAME", o.exercise, "anchor-5, anchor-7 or an exercise file (.json)")
      ->required();
  plan->add_option("--out", o.out, "The path CSV to write (for drill --path and score)")
      ->required();
  addUp(*plan, o.up);
  addJson(*plan, o.json);
  plan->callback([&o] { o.which = "plan"; });
}

void addScore(CLI::App& cmd, ScoreCommandOptions& o) {
  cmd.add_option("TRIAL", o.path,
                 "A path CSV (the viewer's or exercise plan's) or a device recording (drill "
                 "--device ... --record)")
      ->required();
  cmd.add_option("--exercise", o.exercise, "anchor-5, anchor-7 or an exercise file (.json)")
      ->required();
  addUp(cmd, o.up);
  cmd.add_option("--out-dir", o.outDir,
                 "Folder for drill's files and score.json, score.html, score.png")
      ->default_val(".");
  addJson(cmd, o.json, "Print the score as JSON on stdout");
}

void addModel(CLI::App& cmd, ModelOptions& o) {
  cmd.add_option("--out", o.out, "Mesh file to write (.stl .obj .ply .off)");
  addJson(cmd, o.json);
}

// A row of the table: the options live as long as the run closure that reads them.
template <typename Options>
Subcommand row(const char* name, const char* help, void (*add)(CLI::App&, Options&),
               int (*run)(const Options&)) {
  return {name, help, [add, run](CLI::App& command) {
            auto options = std::make_shared<Options>();
            add(command, *options);
            return std::function<int()>([options, run] { return run(*options); });
          }};
}

}  // namespace

const std::vector<Subcommand>& subcommands() {
  static const std::vector<Subcommand> table = {
      row("info", "Print a mesh's size, bounds, volume and topology, or a DICOM folder's series",
          addInfo, runInfo),
      row("voxelize", "Voxelize a mesh by Embree ray projection (seed 3.2)", addVoxelize,
          runVoxelize),
      row("hierarchy",
          "Build the Dynamic Proximity Hierarchy over a voxelized mesh or grid (seed 3.3)",
          addHierarchy, runHierarchy),
      row("mesh",
          "Extract the crack-free (or the seed's naive) surface of a voxelized mesh or grid",
          addMeshCommand, runMesh),
      row("drill",
          "Drill a path into the bone at 1 kHz (deterministic): force log, summary, surface",
          addDrill, runDrill),
      row("replay",
          "Replay a device recording through the safety layer into a deterministic session",
          addReplay, runReplay),
      row("devices", "List attached devices, or watch one's events", addDevices, runDevices),
      row("check", "Prove a surface crack-free: exact checks (CGAL), pixel crack metric, accuracy",
          addCheck, runCheck),
      row("validate",
          "The nightly run: every guarantee on models x voxel sizes x methods x modes; report",
          addValidate, runValidate),
      row("experiment",
          "Rerun a paper experiment: 'seed' is section 4 (static vs dynamic force plots), 'heat' "
          "Augustin 2008's drilling temperatures",
          addExperiment, runExperiment),
      row("exercise", "The exercises: list them, show one, write one's planned path", addExercise,
          runExercise),
      row("score",
          "Drill a path or replay a device recording into an exercise's bone and score it "
          "against the plan",
          addScore, runScore),
      row("model",
          "Build the built-in proximal humerus (what 'default' means) and optionally write it",
          addModel, runModel),
  };
  return table;
}

}  // namespace osteon::cli
