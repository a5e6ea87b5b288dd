// `osteon experiment seed`: the seed's section 4 rerun. Force logs per run, the jitter table
// (Markdown and JSON) and force plots in the manner of the seed's Figs. 6-8, drawn by gnuplot.
#include "commands/experiment.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/geometry/io/mesh_source.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/simulation/experiment.h"
#include "support/files.h"
#include "support/force_plots.h"
#include "support/output.h"

namespace osteon::cli {

namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

std::string runLabel(const sim::ExperimentRun& r) {
  std::ostringstream s;
  if (r.levels == 0) {
    s << "static " << r.voxelSizeMm << " mm";
  } else {
    s << "dynamic " << r.levels << " level" << (r.levels > 1 ? "s" : "") << " ("
      << r.voxelSizeMm / double(1 << r.levels) << " mm)";
  }
  return s.str();
}

// One figure per voxel size and portal, static and dynamic on the same axes (seed Figs. 6-8).
std::vector<ForceFigure> figuresOf(const std::string& dir,
                                   const std::vector<sim::ExperimentRun>& runs,
                                   std::vector<std::string>& images) {
  std::map<std::pair<double, int>, std::vector<const sim::ExperimentRun*>> byCase;
  for (const sim::ExperimentRun& r : runs) byCase[{-r.voxelSizeMm, int(r.portal)}].push_back(&r);
  std::vector<ForceFigure> figures;
  int number = 6;
  double lastSize = 0.0;
  for (const auto& [key, members] : byCase) {
    const double size = -key.first;
    if (lastSize != 0.0 && size != lastSize) ++number;
    lastSize = size;
    const sim::ExperimentRun& first = *members.front();
    std::ostringstream file, title;
    file << "fig" << number << "_" << size << "mm_" << sim::portalName(first.portal) << ".png";
    title << "VS = " << size << " mm, " << sim::portalName(first.portal)
          << (first.portal == sim::Portal::FiveOClock ? " (anteroinferior)" : " (posteroinferior)")
          << ": static and dynamic voxels";
    images.push_back(file.str());
    ForceFigure figure{dir + "/" + file.str(), title.str(), {}};
    for (const sim::ExperimentRun* m : members) {
      figure.series.push_back(
          {dir + "/runs/" + m->name() + "/forces.csv", runLabel(*m), m->levels == 0 ? 1.2 : 1.6});
    }
    figures.push_back(std::move(figure));
  }
  return figures;
}

// The runs as the seed compares its figures: jitter per run, as experiment.json (the JSON) and
// jitter.md (the text).
struct ExperimentReport {
  std::string mesh;
  std::string outDir;
  const std::vector<sim::ExperimentRun>* runs = nullptr;
  std::vector<std::string> images;  // the plots, relative to outDir
};

double finestVoxelMm(const sim::ExperimentRun& r) {
  return r.voxelSizeMm / double(1 << r.levels);
}

json toJson(const ExperimentReport& report) {
  json rows = json::array();
  for (const sim::ExperimentRun& r : *report.runs) {
    const sim::RunSummary& s = r.result.summary;
    rows.push_back({{"voxel_size_mm", r.voxelSizeMm},
                    {"portal", sim::portalName(r.portal)},
                    {"levels", r.levels},
                    {"finest_voxel_mm", finestVoxelMm(r)},
                    {"jitter_n", s.jitterN},
                    {"max_step_change_n", s.maxStepChangeN},
                    {"max_force_n", s.maxForceN},
                    {"removed_volume_mm3", s.removedVolumeMm3},
                    {"steps", s.steps},
                    {"log", "runs/" + r.name() + "/forces.csv"}});
  }
  return {{"experiment", "seed"}, {"mesh", report.mesh}, {"runs", rows}, {"plots", report.images}};
}

std::string jitterTable(const ExperimentReport& report) {
  std::ostringstream md;
  md << "| voxel size | portal | levels | force voxel | jitter (N) | max step change (N) | max "
        "force (N) | removed (mm3) |\n"
     << "|---:|---|---:|---:|---:|---:|---:|---:|\n";
  for (const sim::ExperimentRun& r : *report.runs) {
    const sim::RunSummary& s = r.result.summary;
    char line[256];
    std::snprintf(line, sizeof line, "| %g mm | %s | %d | %g mm | %.4f | %.4f | %.3f | %.1f |\n",
                  r.voxelSizeMm, sim::portalName(r.portal), r.levels, finestVoxelMm(r), s.jitterN,
                  s.maxStepChangeN, s.maxForceN, s.removedVolumeMm3);
    md << line;
  }
  return md.str();
}

void printText(const ExperimentReport& report) {
  std::cout << jitterTable(report) << "plots: ";
  for (const std::string& i : report.images) std::cout << report.outDir << "/" << i << " ";
  std::cout << "\n";
}

// A volume's experiment runs on its surface, extracted crack-free at the volume's own voxels and
// voxelized at each case's size as any mesh is: the seed's voxel sizes are not a volume's.
sim::BoneMesh experimentMesh(const sim::BoneSource& source) {
  if (!source.isVolume()) return sim::loadBoneMesh(source);
  const sim::OpenedBone opened = sim::BoneModel::open(source);
  return {
      geometry::extractSurface(opened.bone->grid(), geometry::SurfaceOptions{}).toTriangleMesh(),
      opened.read};
}

}  // namespace

int runExperiment(const ExperimentCommandOptions& given) {
  ExperimentCommandOptions options = given;
  if (options.outDir.empty()) options.outDir = "experiment-" + options.name;
  if (options.name == "thrust") return runThrustExperiment(options, options.outDir);
  if (options.name == "heat") return runHeatExperiment(options);
  if (options.name != "seed")
    throw InputError("experiment " + options.name + ": unknown (expected seed, thrust or heat)");
  const std::vector<sim::ExperimentCase> cases = sim::seedExperimentCases();
  // Every file the run will write, checked against the mesh before any work.
  std::vector<sim::ExperimentRun> planned;
  for (const sim::ExperimentCase& c : cases) {
    for (const sim::Portal portal : {sim::Portal::FiveOClock, sim::Portal::SevenOClock}) {
      planned.push_back({c.voxelSizeMm, portal, 0, {}});
      for (const int l : c.dynamicLevels) planned.push_back({c.voxelSizeMm, portal, l, {}});
    }
  }
  std::vector<std::string> outputs = {options.outDir + "/experiment.json",
                                      options.outDir + "/jitter.md", options.outDir + "/plots.gp"};
  std::vector<std::string> plannedImages;
  figuresOf(options.outDir, planned, plannedImages);
  for (const std::string& image : plannedImages) outputs.push_back(options.outDir + "/" + image);
  geometry::refuseOverwritingInputs(outputs, options.bone.inputFiles());
  refuseInputsInside(options.outDir + "/runs", options.bone.inputFiles());

  // The logs, the table and the plots are one set, put in place together when the run is
  // complete (output_dir.h). plots.gp.log is gnuplot's own say, not part of it.
  std::vector<std::string> owned = {"runs", "experiment.json", "jitter.md", "plots.gp"};
  owned.insert(owned.end(), plannedImages.begin(), plannedImages.end());
  geometry::OutputDir outDir(options.outDir, owned);
  std::error_code ec;
  std::filesystem::create_directories(options.outDir + "/runs", ec);
  if (ec)
    throw InputError("--out-dir " + options.outDir + ": cannot create the folder (" + ec.message() +
                     ")");
  const sim::BoneMesh loaded = experimentMesh(options.bone);
  const geometry::TriangleMesh& mesh = loaded.mesh;
  const double scale = loaded.read.scaleToMm;
  geometry::VoxelizeOptions voxelizing;
  voxelizing.meshName = options.bone.input;
  voxelizing.loadScaleToMm = scale;

  const std::vector<sim::ExperimentRun> runs = sim::runSeedExperiment(
      mesh, cases,
      [&](const sim::ExperimentRun& r) {
        throwIfInterrupted();  // a run cut short by SIGINT/SIGTERM: nothing is put in place
        const std::string dir = options.outDir + "/runs/" + r.name();
        std::filesystem::create_directories(dir);
        sim::writeForceLog(r.result.log, dir + "/forces.csv");
        if (!options.json) {
          std::cerr << "  " << r.name() << ": jitter " << r.result.summary.jitterN << " N\n";
        }
      },
      voxelizing,
      options.bone.up.empty() ? std::nullopt
                              : std::optional<glm::dvec3>(sim::parseUpAxis(options.bone.up)));

  ExperimentReport report{options.bone.input, options.outDir, &runs, {}};
  const std::vector<ForceFigure> figures = figuresOf(options.outDir, runs, report.images);
  geometry::writeFileAtomically(options.outDir + "/experiment.json", toJson(report).dump(2) + "\n");
  geometry::writeFileAtomically(options.outDir + "/jitter.md", jitterTable(report));
  // The logs and the table are kept when the plotting fails (gnuplot missing): a set without
  // plots, the previous run's plots removed.
  try {
    drawForcePlots(figures, options.outDir + "/plots.gp");
  } catch (const InputError&) {
    outDir.commit();
    throw;
  }
  outDir.commit();
  printReport(report, options.json);
  return kExitOk;
}

}  // namespace osteon::cli
