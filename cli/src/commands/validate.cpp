// `osteon validate`: the nightly run and its report (report.json with a stable schema,
// report.html, validate.log, crack images), or a shard of the run (--shard K/N); merging the
// shards' reports is validate_merge.cpp.
#include "osteon/validation/validate.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands/validate_report.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/runner.h"
#include "osteon/validation/crack_images.h"
#include "osteon/validation/shard.h"
#include "support/files.h"
#include "support/force_plots.h"

namespace osteon::cli {

using nlohmann::json;
namespace sim = osteon::simulation;
namespace val = osteon::validation;

namespace {

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

std::vector<double> parseVoxelSizes(const std::string& text) {
  std::vector<double> sizes;
  for (const std::string& item : splitList(text)) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || !(v >= 0.1 && v <= 10.0)) {
      throw InputError("--voxel-sizes " + text + ": '" + item +
                       "' is not a voxel size in 0.1..10 mm");
    }
    sizes.push_back(v);
  }
  if (sizes.empty()) throw InputError("--voxel-sizes " + text + ": no voxel size given");
  return sizes;
}

std::map<std::string, std::string> modelFileNames(const std::vector<std::string>& models) {
  std::map<std::string, std::string> stemOf;
  std::map<std::string, std::set<std::string>> argumentsOf;
  for (const std::string& model : models) {
    std::string stem;
    for (const char ch : std::filesystem::path(model).stem().string()) {
      stem += std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-' || ch == '_'
                  ? ch
                  : '_';
    }
    if (stem.empty()) stem = "model";
    stemOf[model] = stem;
    argumentsOf[stem].insert(model);
  }
  std::map<std::string, std::string> names;
  for (const auto& [model, stem] : stemOf) {
    if (argumentsOf[stem].size() == 1) {
      names[model] = stem;
      continue;
    }
    std::uint32_t hash = 2166136261u;  // FNV-1a: stable across runs, machines and shards
    for (const char ch : model) hash = (hash ^ static_cast<unsigned char>(ch)) * 16777619u;
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "-%08x", hash);
    names[model] = stem + suffix;
  }
  return names;
}

// --shard K/N: whole decimal numbers, K counted from 0 (as a Slurm array's task ids).
std::pair<std::size_t, std::size_t> parseShard(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return InputError("--shard " + text + ": " + why);
  };
  const std::size_t slash = text.find('/');
  const auto whole = [](const std::string& t) {
    return !t.empty() && t.size() <= 9 &&
           std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (slash == std::string::npos || !whole(text.substr(0, slash)) ||
      !whole(text.substr(slash + 1))) {
    throw bad("not K/N with whole numbers, K counted from 0 (0/4 .. 3/4)");
  }
  const std::size_t k = std::stoul(text.substr(0, slash)), n = std::stoul(text.substr(slash + 1));
  if (n == 0) throw bad("N must be at least 1");
  if (k >= n)
    throw bad("K must be below N (shards are counted from 0: 0.." + std::to_string(n - 1) + ")");
  return {k, n};
}

// Each model as validation takes it: a mesh read and scaled, or a volume at its own voxel size
// (every non-background label or 300 HU: `osteon mesh VOLUME` says what it holds).
std::vector<val::ValidationModel> loadModels(const ValidateCommandOptions& options,
                                             const std::vector<std::string>& names) {
  std::vector<val::ValidationModel> models;
  for (const std::string& name : names) {
    sim::BoneSource model = options.source;
    model.input = name;
    models.emplace_back();
    models.back().name = name;
    if (model.isVolume()) {
      model.forSession = false;
      models.back().volume = sim::BoneModel::open(model).bone->grid();
      if (models.back().volume->countVoxels(geometry::kFillHalf) == 0) {
        throw InputError(name + ": no voxel inside (nothing to validate)");
      }
    } else {
      sim::BoneMesh loaded = sim::loadBoneMesh(model);
      models.back().mesh = std::move(loaded.mesh);
      models.back().loadScaleToMm = loaded.read.scaleToMm;
    }
  }
  return models;
}

// The case groups of the run, and which of them this shard runs (shard.h; every shard computes
// the same split). vo.groups is set to the shard's.
struct ShardPlan {
  std::vector<val::CaseGroup> groups;
  std::vector<bool> ownGroup;
  std::vector<std::string> runKeys;
};

ShardPlan planShards(const ValidateCommandOptions& options,
                     const std::vector<val::ValidationModel>& models, val::ValidationOptions& vo,
                     std::size_t shardIndex, std::size_t shardCount) {
  ShardPlan plan;
  plan.groups = val::caseGroups(models, vo);
  plan.ownGroup.assign(plan.groups.size(), true);
  plan.runKeys = val::caseKeys(models, plan.groups);
  if (options.shard.empty()) return plan;
  // A merge finds each case by its key, so a model or voxel size given twice cannot be split.
  std::set<std::string> unique;
  for (const std::string& key : plan.runKeys) {
    if (!unique.insert(key).second) {
      throw InputError("--shard " + options.shard + ": case " + key +
                       " comes twice (a model or voxel size given twice)");
    }
  }
  std::vector<double> costs;
  for (const val::CaseGroup& g : plan.groups) costs.push_back(g.cost);
  const std::vector<std::size_t> shardOf = val::assignShards(costs, shardCount);
  vo.groups.emplace();
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    plan.ownGroup[g] = shardOf[g] == shardIndex;
    if (plan.ownGroup[g]) vo.groups->push_back(g);
  }
  return plan;
}

// What each finished case leaves: the force logs of its crack-free runs (for the plots:
// forces/<model>_<voxel>_<mode>_<portal>.csv) and one line on stdout and in the log.
class CaseRecorder {
 public:
  CaseRecorder(const std::string& outDir, const std::map<std::string, std::string>& fileNameOf,
               std::size_t total, std::ofstream& log)
      : outDir_(outDir), fileNameOf_(fileNameOf), total_(total), log_(log) {}

  void operator()(const val::ValidationCase& c) {
    throwIfInterrupted();  // a case cut short by SIGINT/SIGTERM: the run ends, nothing put in place
    if (c.method == geometry::SurfaceMethod::CrackFree) {
      for (const val::PortalRun& p : c.portals) keepForceLog(c, p);
    }
    std::ostringstream line;
    line << "[" << ++done_ << "/" << total_ << "] " << c.model << " " << c.voxelSizeMm << " mm "
         << geometry::surfaceMethodName(c.method) << " " << val::forceModeName(c.mode) << ": ";
    if (c.method == geometry::SurfaceMethod::Naive) {
      line << (c.pass() ? "baseline keeps the guarantees (unexpected)"
                        : "baseline breaks the guarantees, as expected");
    } else {
      line << (c.pass() ? "pass" : "FAIL");
    }
    for (const std::string& f : c.failures) line << "; " << f;
    std::cout << line.str() << "\n" << std::flush;
    log_ << line.str() << "\n" << std::flush;
  }

  // model, voxel size, portal -> runs
  const std::map<std::string, std::vector<ForceSeries>>& plotGroups() const { return plotGroups_; }

 private:
  void keepForceLog(const val::ValidationCase& c, const val::PortalRun& p) {
    std::ostringstream stem, group;
    stem << "forces/" << fileNameOf_.at(c.model) << "_" << c.voxelSizeMm << "mm_"
         << val::forceModeName(c.mode) << "_" << p.portal << ".csv";
    group << fileNameOf_.at(c.model) << ", VS = " << c.voxelSizeMm << " mm, " << p.portal;
    simulation::writeForceLog(p.collisions.run.log, outDir_ + "/" + stem.str());
    std::ostringstream label;
    const bool still = c.mode == val::ForceMode::Static;
    label << val::forceModeName(c.mode) << (still ? " " : " 2 levels, ")
          << c.voxelSizeMm / (still ? 1.0 : 4.0) << " mm";
    plotGroups_[group.str()].push_back(
        {outDir_ + "/" + stem.str(), label.str(), still ? 1.2 : 1.6});
  }

  std::string outDir_;
  const std::map<std::string, std::string>& fileNameOf_;
  std::size_t total_ = 0, done_ = 0;
  std::ofstream& log_;
  std::map<std::string, std::vector<ForceSeries>> plotGroups_;
};

// Crack views of each model's surfaces at the first voxel size, before drilling; in a shard, of
// the models whose first group it runs. Returns their paths relative to outDir.
std::vector<std::string> writeModelImages(const std::vector<val::ValidationModel>& models,
                                          const ShardPlan& plan, double voxelSizeMm,
                                          const std::string& outDir) {
  std::vector<bool> ownImages(models.size(), false);
  for (std::size_t g = plan.groups.size(); g-- > 0;)
    ownImages[plan.groups[g].model] = plan.ownGroup[g];
  std::vector<std::string> images;
  for (const val::ValidationModel& m : models) {
    if (!ownImages[static_cast<std::size_t>(&m - models.data())]) continue;
    geometry::VoxelizeOptions gv;
    gv.voxelSizeMm = voxelSizeMm;
    gv.requireInside = true;
    gv.meshName = m.name;
    gv.loadScaleToMm = m.loadScaleToMm;
    const geometry::VoxelGrid grid = m.volume ? *m.volume : geometry::voxelize(m.mesh, gv);
    for (const char* method : {"crackfree", "naive"}) {
      geometry::SurfaceOptions so;
      so.method = std::string(method) == "naive" ? geometry::SurfaceMethod::Naive
                                                 : geometry::SurfaceMethod::CrackFree;
      const std::string dir =
          outDir + "/images/" + std::to_string(&m - models.data()) + "_" + method;
      const geometry::TriangleMesh surface = geometry::extractSurface(grid, so).toTriangleMesh();
      for (const std::string& p : val::writeCrackImagesOf(surface, 256, dir)) {
        images.push_back(std::filesystem::relative(p, outDir).string());
      }
    }
  }
  return images;
}

// Static against dynamic per model, voxel size and portal, as the seed's Figs. 6-8; returns the
// plots' paths relative to outDir, sorted (as a merge lists the shards' plots).
std::vector<std::string> drawPlots(
    const std::map<std::string, std::vector<ForceSeries>>& plotGroups, const std::string& outDir) {
  std::vector<ForceFigure> figures;
  std::vector<std::string> plots;
  std::filesystem::create_directories(outDir + "/plots");
  for (const auto& [group, series] : plotGroups) {
    std::string name;  // the title, as a file name
    for (const char ch : group) {
      if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-')
        name += ch;
      else if (!name.empty() && name.back() != '_')
        name += '_';
    }
    figures.push_back(
        {outDir + "/plots/" + name + ".png", group + ": static and dynamic voxels", series});
    plots.push_back("plots/" + name + ".png");
  }
  if (!figures.empty()) drawForcePlots(figures, outDir + "/plots/plots.gp");
  std::sort(plots.begin(), plots.end());
  return plots;
}

// The whole run's case list, so a merge can tell shards of one run from shards of another.
json shardJson(const ShardPlan& plan, std::size_t shardIndex, std::size_t shardCount) {
  json own = json::array();
  double cost = 0.0, totalCost = 0.0;
  for (std::size_t g = 0; g < plan.groups.size(); ++g) {
    totalCost += plan.groups[g].cost;
    if (!plan.ownGroup[g]) continue;
    cost += plan.groups[g].cost;
    for (int k = 0; k < val::kCasesPerGroup; ++k)
      own.push_back(plan.runKeys[g * std::size_t(val::kCasesPerGroup) + std::size_t(k)]);
  }
  return {{"index", shardIndex}, {"count", shardCount},    {"case_list", plan.runKeys},
          {"cases", own},        {"estimated_cost", cost}, {"run_estimated_cost", totalCost}};
}

}  // namespace

int runValidate(const ValidateCommandOptions& options) {
  if (!options.merge.empty()) return runValidateMerge(options);
  options.source.check();  // the models' units or scale, before any work
  // Plain values, not an optional pair: GCC's -Wmaybe-uninitialized misreads the latter.
  const bool sharded = !options.shard.empty();
  const auto [shardIndex, shardCount] =
      sharded ? parseShard(options.shard) : std::pair<std::size_t, std::size_t>{0, 1};
  // Sizes given with --quick replace its 1.2 mm; given or not, they are checked.
  const std::vector<double> parsedSizes = parseVoxelSizes(options.voxelSizes);
  const std::vector<double> sizes =
      options.quick && !options.voxelSizesGiven ? std::vector<double>{1.2} : parsedSizes;
  const std::vector<std::string> names = splitList(options.models);
  if (names.empty()) throw InputError("--models " + options.models + ": no model given");
  const json old = options.compare.empty() ? json() : readComparable(options.compare);
  std::vector<std::string> inputs;
  for (const std::string& name : names) {
    sim::BoneSource model = options.source;
    model.input = name;
    for (const std::string& file : model.inputFiles()) inputs.push_back(file);
  }
  inputs.push_back(options.compare);
  const std::string logPath = options.outDir + "/validate.log";
  geometry::refuseOverwritingInputs(
      {options.outDir + "/report.json", options.outDir + "/report.html", logPath}, inputs);
  for (const char* owned : {"/forces", "/plots", "/images"})
    refuseInputsInside(options.outDir + owned, inputs);
  // The report, the log, the force logs, plots and images are one set, put in place together
  // when the run is complete (output_dir.h).
  geometry::OutputDir outDir(
      options.outDir, {"report.json", "report.html", "validate.log", "forces", "plots", "images"});
  std::error_code ec;
  std::filesystem::create_directories(options.outDir + "/images", ec);
  if (ec)
    throw InputError("--out-dir " + options.outDir + ": cannot create the folder (" + ec.message() +
                     ")");
  const std::map<std::string, std::string> fileNameOf = modelFileNames(names);
  const std::vector<val::ValidationModel> models = loadModels(options, names);

  val::ValidationOptions vo;
  vo.voxelSizesMm = sizes;
  vo.crackPixels = options.quick ? 256 : 512;
  vo.checkEverySteps = options.quick ? 25 : 10;
  geometry::OutputFile logFile(logPath);
  std::ofstream log(logFile.tempPath());
  const auto started = std::chrono::system_clock::now();
  const std::time_t startedT = std::chrono::system_clock::to_time_t(started);
  char startedText[32];
  std::strftime(startedText, sizeof startedText, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&startedT));
  const ShardPlan plan = planShards(options, models, vo, shardIndex, shardCount);
  const std::size_t total =
      static_cast<std::size_t>(std::count(plan.ownGroup.begin(), plan.ownGroup.end(), true)) *
      val::kCasesPerGroup;
  std::filesystem::create_directories(options.outDir + "/forces");
  CaseRecorder recorder(options.outDir, fileNameOf, total, log);
  const val::ValidationReport report =
      val::runValidation(models, vo, [&recorder](const val::ValidationCase& c) { recorder(c); });
  const std::vector<std::string> images =
      writeModelImages(models, plan, sizes.front(), options.outDir);
  const std::vector<std::string> plots = drawPlots(recorder.plotGroups(), options.outDir);

  json cases = json::array();
  for (const val::ValidationCase& c : report.cases) cases.push_back(caseJson(c));
  const double seconds =
      std::chrono::duration<double>(std::chrono::system_clock::now() - started).count();
  json j = {{"schema", "osteon-validate/1"},
            {"started", startedText},
            {"seconds", seconds},
            {"osteon_version", OSTEON_VERSION},
            {"options",
             {{"models", names},
              {"voxel_sizes_mm", sizes},
              {"quick", options.quick},
              {"crack_pixels", vo.crackPixels},
              {"collision_check_every_steps", vo.checkEverySteps}}},
            {"environment", environmentJson()},
            {"cases", cases},
            {"plots", plots},
            {"regressions", json::array()}};
  if (sharded) j["shard"] = shardJson(plan, shardIndex, shardCount);
  writeReport(j, options, old, images);
  log.close();
  if (!log) throw InputError(logPath + ": writing failed (disk full or not writable?)");
  logFile.commit();
  outDir.commit();
  return printVerdict(j, options.outDir);
}

}  // namespace osteon::cli
