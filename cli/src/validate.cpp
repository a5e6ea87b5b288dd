// `osteon validate`: the nightly run and its report (report.json with a stable schema,
// report.html, validate.log, crack images), or a shard of the run (--shard K/N); merging the
// shards' reports is validate_merge.cpp.
#include "validate_report.h"

#include "commands.h"
#include "force_plots.h"

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/geometry/io/library_versions.h"
#include "osteon/geometry/io/mesh_source.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/io/volume_io.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/runner.h"
#include "osteon/validation/library_versions.h"
#include "osteon/validation/shard.h"
#include "osteon/validation/validate.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <sys/utsname.h>

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
      throw InputError("--voxel-sizes " + text + ": '" + item + "' is not a voxel size in 0.1..10 mm");
    }
    sizes.push_back(v);
  }
  if (sizes.empty()) throw InputError("--voxel-sizes " + text + ": no voxel size given");
  return sizes;
}

json surfaceJson(const val::MeshReport& r, const val::CrackMetric& c) {
  return {{"border_edges", r.topology.borderEdges},
          {"non_manifold", r.topology.nonManifoldEdges + r.topology.nonManifoldVertices},
          {"self_intersections", r.selfIntersections},
          {"self_intersections_capped", r.selfIntersectionsCapped},
          {"outward_oriented", r.outwardOriented},
          {"components", r.topology.components},
          {"genus", r.genus},
          {"crack_percent", c.crackPercent()},
          {"red_pixels", c.red}};
}

json caseJson(const val::ValidationCase& c) {
  std::uint64_t misses = 0, falseContacts = 0, checked = 0, nonFinite = 0, rays = 0, missedSamples = 0;
  std::uint64_t boundary = 0, skipped = 0;
  double maxForce = 0.0, jitter = 0.0, worstMiss = 0.0;
  json portals = json::array();
  for (const val::PortalRun& p : c.portals) {
    misses += p.collisions.misses;
    falseContacts += p.collisions.falseContacts;
    checked += p.collisions.checked;
    rays += p.collisions.raysCast;
    missedSamples += p.collisions.missedSamples;
    boundary += p.collisions.boundarySamples;
    skipped += p.collisions.skippedSamples;
    worstMiss = std::max(worstMiss, p.collisions.worstMissMm);
    nonFinite += p.nonFiniteForces;
    maxForce = std::max(maxForce, p.maxForceN);
    jitter = std::max(jitter, p.jitterN);
    portals.push_back({{"portal", p.portal}, {"collision_misses", p.collisions.misses},
                       {"false_contacts", p.collisions.falseContacts}, {"checked_steps", p.collisions.checked},
                       {"contacts", p.collisions.contacts}, {"contact_samples", p.collisions.contactSamples},
                       {"boundary_samples", p.collisions.boundarySamples},
                       {"skipped_samples", p.collisions.skippedSamples}, {"skipped_steps", p.collisions.skippedSteps},
                       {"rays_cast", p.collisions.raysCast}, {"missed_samples", p.collisions.missedSamples},
                       {"worst_miss_mm", p.collisions.worstMissMm}, {"max_force_n", p.maxForceN},
                       {"jitter_n", p.jitterN}, {"removed_volume_mm3", p.collisions.run.summary.removedVolumeMm3}});
  }
  json j = {{"model", c.model},
            {"voxel_size_mm", c.voxelSizeMm},
            {"method", geometry::surfaceMethodName(c.method)},
            {"mode", val::forceModeName(c.mode)},
            {"pass", c.pass()},
            {"failures", c.failures},
            {"border_edges", c.before.topology.borderEdges},
            {"non_manifold", c.before.topology.nonManifoldEdges + c.before.topology.nonManifoldVertices},
            {"self_intersections", c.before.selfIntersections},
            {"crack_percent", c.cracks.crackPercent()},
            {"hausdorff_mm", c.accuracyKnown ? json(c.accuracy.hausdorffMm) : json(nullptr)},
            {"hausdorff_voxels", c.accuracyKnown ? json(c.accuracy.hausdorffMm / c.voxelSizeMm) : json(nullptr)},
            {"volume_difference_percent", c.accuracyKnown ? json(c.accuracy.volumeDifferencePercent) : json(nullptr)},
            {"collision_misses", misses},
            {"false_contacts", falseContacts},
            {"collision_checks", checked},
            {"collision_rays", rays},
            {"collision_missed_samples", missedSamples},
            {"collision_boundary_samples", boundary},
            {"collision_skipped_samples", skipped},
            {"collision_worst_miss_mm", worstMiss},
            {"max_force_n", maxForce},
            {"jitter_n", jitter},
            {"non_finite_forces", nonFinite},
            {"triangles", c.triangles},
            {"vertices", c.vertices},
            {"voxels", c.voxels},
            {"extract_ms", c.extractMs},
            {"case_ms", {{"setup", c.setupMs}, {"surface", c.surfaceMs}, {"drill", c.drillMs}}},
            {"mesh_time_ms", {{"total", c.timings.totalMs}, {"extract", c.timings.extractMs},
                              {"smooth", c.timings.smoothMs}, {"normals", c.timings.normalsMs},
                              {"other", c.timings.otherMs}}},
            {"before", surfaceJson(c.before, c.cracks)},
            {"portals", portals}};
  if (!c.portals.empty()) j["after"] = surfaceJson(c.after, c.afterCracks);
  return j;
}

// What produced the numbers: compiler, build, the libraries linked, the machine.
json environmentJson() {
  json libraries = json::object();
  for (const auto& [name, version] : geometry::libraryVersions()) libraries[name] = version;
  for (const auto& [name, version] : val::libraryVersions()) libraries[name] = version;
  std::string os = "unknown";
  utsname u{};
  if (uname(&u) == 0) os = std::string(u.sysname) + " " + u.release + " " + u.machine;
  std::string cpu = "unknown";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    const std::size_t start = colon == std::string::npos ? colon : line.find_first_not_of(" \t", colon + 1);
    if (start != std::string::npos) cpu = line.substr(start);
    break;
  }
  const std::string buildType = OSTEON_BUILD_TYPE;
  return {{"compiler", __VERSION__}, {"cpp", __cplusplus}, {"build_type", buildType.empty() ? "unset" : buildType},
          {"hardware_threads", std::thread::hardware_concurrency()}, {"os", os}, {"cpu", cpu},
          {"libraries", libraries}};
}

// Regressions against an older report: a case that passed and fails, or a crack-free metric
// that got worse (counts up at all; distances and jitter by more than 10 %).
json compareReports(const json& now, const json& old) {
  std::map<std::string, const json*> before;
  for (const json& c : old["cases"]) before[caseKey(c)] = &c;
  json regressions = json::array();
  for (const json& c : now["cases"]) {
    const auto it = before.find(caseKey(c));
    if (it == before.end()) continue;
    const json& o = *it->second;
    const auto note = [&](const std::string& what) { regressions.push_back({{"case", caseKey(c)}, {"what", what}}); };
    if (o.value("pass", false) && !c.value("pass", false)) note("passed before, fails now");
    if (c.value("method", "") != "crackfree") continue;
    // Both reports are checked (readComparable, readShard, or written here): a count is a whole
    // number of 64 bits, a distance a finite number; a field the old report lacks is not compared.
    for (const char* k : {"border_edges", "non_manifold", "self_intersections", "collision_misses"}) {
      if (!c.contains(k) || !o.contains(k)) continue;
      const std::uint64_t a = o[k].get<std::uint64_t>(), b = c[k].get<std::uint64_t>();
      if (b > a) note(std::string(k) + " " + std::to_string(a) + " -> " + std::to_string(b));
    }
    for (const char* k : {"crack_percent", "hausdorff_mm", "jitter_n"}) {
      if (!c.contains(k) || !c[k].is_number() || !o.contains(k) || !o[k].is_number()) continue;
      const double a = o[k].get<double>(), b = c[k].get<double>();
      if ((std::string(k) == "crack_percent" && b > a) || b > 1.1 * a + 1e-12) {
        note(std::string(k) + " " + std::to_string(a) + " -> " + std::to_string(b));
      }
    }
  }
  return regressions;
}

// Text for report.html, in an element or a double-quoted attribute alike: every character
// that could end either, or start markup, is escaped. Every value the page shows goes through
// here, the numbers too (a dump of a JSON value).
std::string htmlEscape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      case '`': out += "&#96;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string htmlEscape(const json& v) { return htmlEscape(v.is_string() ? v.get<std::string>() : v.dump()); }

// A number for a table cell: four significant digits (the JSON keeps full precision).
std::string cell(const json& v) {
  if (!v.is_number_float()) return htmlEscape(v);
  std::ostringstream out;
  out << std::setprecision(4) << v.get<double>();
  return out.str();
}

void writeHtml(const std::string& path, const json& report, const std::vector<std::string>& images) {
  std::ostringstream h;
  const bool pass = report["verdict"] == "PASS";
  const std::string verdict = htmlEscape(report["verdict"]);
  h << "<!doctype html><html><head><meta charset=\"utf-8\"><title>osteon validation: " << verdict
    << "</title><style>body{font-family:sans-serif;margin:2em}"
    << "table{border-collapse:collapse}td,th{border:1px solid #999;padding:3px 8px;text-align:right}"
    << ".pass{color:#070}.fail{color:#b00;font-weight:bold}img{width:200px;margin:4px;border:1px solid #ccc}</style>"
    << "</head><body>\n<h1>osteon validation: <span class=\"" << (pass ? "pass" : "fail") << "\">" << verdict
    << "</span></h1>\n<p>"
    << (pass ? "Every crack-free case keeps every guarantee."
             : "A crack-free case broke a guarantee: see the failures below.")
    << " The naive method is the seed's baseline, measured beside it and expected to fail.</p>\n";
  h << "<p>Started " << htmlEscape(report["started"]) << ", " << report["seconds"].get<double>() << " s. osteon "
    << htmlEscape(report["osteon_version"]) << ".</p>\n";
  if (report.contains("shard")) {
    const json& shard = report["shard"];
    h << "<p>Shard " << htmlEscape(shard["index"]) << " of " << htmlEscape(shard["count"]) << " (counted from 0): "
      << shard["cases"].size() << " of the run's " << shard["case_list"].size() << " cases; merge the shards with "
      << "<code>osteon validate --merge</code>.</p>\n";
  }
  if (report.contains("merged_from")) {
    h << "<p>Merged from " << report["merged_from"].size() << " shards (the seconds above are their sum):";
    for (const json& d : report["merged_from"]) h << " " << htmlEscape(d);
    h << ".</p>\n";
  }
  if (!report["regressions"].empty()) {
    h << "<h2 class=\"fail\">Regressions against " << htmlEscape(report.value("compared_with", "")) << "</h2><ul>";
    for (const json& r : report["regressions"]) h << "<li>" << htmlEscape(r["case"]) << ": " << htmlEscape(r["what"]) << "</li>";
    h << "</ul>\n";
  }
  h << "<h2>Cases</h2><table><tr><th>model</th><th>voxel</th><th>method</th><th>mode</th><th>verdict</th>"
    << "<th>border edges</th><th>non-manifold</th><th>self-int.</th><th>cracks %</th><th>Hausdorff mm</th>"
    << "<th>collision misses</th><th>rays missed / cast</th><th>max |F| N</th><th>jitter N</th><th>after drilling: border / cracks %</th></tr>\n";
  for (const json& c : report["cases"]) {
    const bool ok = c["pass"].get<bool>();
    h << "<tr><td>" << htmlEscape(c["model"]) << "</td><td>" << htmlEscape(c["voxel_size_mm"]) << " mm</td><td>"
      << htmlEscape(c["method"]) << "</td><td>" << htmlEscape(c["mode"]) << "</td><td class=\""
      << (ok ? "pass\">pass" : "fail\">FAIL") << "</td><td>" << cell(c["border_edges"]) << "</td><td>"
      << cell(c["non_manifold"]) << "</td><td>" << cell(c["self_intersections"]) << "</td><td>"
      << cell(c["crack_percent"]) << "</td><td>" << cell(c["hausdorff_mm"]) << "</td><td>" << cell(c["collision_misses"])
      << "</td><td>" << cell(c["collision_missed_samples"]) << " / " << cell(c["collision_rays"]) << "</td><td>"
      << cell(c["max_force_n"]) << "</td><td>" << cell(c["jitter_n"]) << "</td><td>";
    if (c.contains("after")) h << cell(c["after"]["border_edges"]) << " / " << cell(c["after"]["crack_percent"]);
    h << "</td></tr>\n";
  }
  h << "</table>\n";
  // The seed's Tables 1 and 2 (built-in humerus there: ViRCAST's own model) beside ours.
  h << "<h2>Mesh creation beside the seed's Tables 1 and 2</h2><table><tr><th>model</th><th>voxel</th>"
    << "<th>voxels</th><th>triangles</th><th>vertices</th><th>mesh ms</th><th>extract</th><th>smooth</th>"
    << "<th>normals</th><th>other</th><th>seed's mesh ms</th></tr>\n";
  for (const json& c : report["cases"]) {
    if (c["method"] != "crackfree" || c["mode"] != "static") continue;
    const double vs = c["voxel_size_mm"].get<double>();
    const char* seed = std::abs(vs - 1.2) < 1e-9 ? "6" : std::abs(vs - 0.9) < 1e-9 ? "14"
                     : std::abs(vs - 0.72) < 1e-9 ? "20" : std::abs(vs - 0.54) < 1e-9 ? "34" : "-";
    const json& t = c["mesh_time_ms"];
    h << "<tr><td>" << htmlEscape(c["model"]) << "</td><td>" << vs << " mm</td><td>" << cell(c["voxels"])
      << "</td><td>" << cell(c["triangles"]) << "</td><td>" << cell(c["vertices"]) << "</td><td>" << cell(t["total"])
      << "</td><td>" << cell(t["extract"]) << "</td><td>" << cell(t["smooth"]) << "</td><td>" << cell(t["normals"])
      << "</td><td>" << cell(t["other"]) << "</td><td>" << seed << "</td></tr>\n";
  }
  h << "</table>\n<h2>Failures</h2><ul>";
  for (const json& c : report["cases"]) {
    for (const json& f : c["failures"]) h << "<li>" << htmlEscape(caseKey(c)) << ": " << htmlEscape(f) << "</li>";
  }
  h << "</ul>\n<h2>Crack views (seed 3.4: front faces white, back faces red)</h2>\n";
  for (const std::string& img : images) h << "<img src=\"" << htmlEscape(img) << "\" title=\"" << htmlEscape(img) << "\">";
  h << "\n<h2>Forces (as the seed's Figs. 6-8)</h2>\n";
  for (const json& p : report["plots"]) h << "<img style=\"width:550px\" src=\"" << htmlEscape(p) << "\">";
  h << "\n<h2>Environment</h2><pre>" << htmlEscape(report["environment"].dump(2)) << "</pre></body></html>\n";
  geometry::writeFileAtomically(path, h.str());
}

// The name each model's force logs and plots go by: its file stem as a file name (letters,
// digits, '.', '-', '_'), plus a short hash of its argument when two models would share it
// (default and big/default.obj), so no model's logs overwrite another's. The same --models
// give the same names in every shard of a run.
std::map<std::string, std::string> modelFileNames(const std::vector<std::string>& models) {
  std::map<std::string, std::string> stemOf;
  std::map<std::string, std::set<std::string>> argumentsOf;
  for (const std::string& model : models) {
    std::string stem;
    for (const char ch : std::filesystem::path(model).stem().string()) {
      stem += std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-' || ch == '_' ? ch : '_';
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
  const auto bad = [&](const std::string& why) { return InputError("--shard " + text + ": " + why); };
  const std::size_t slash = text.find('/');
  const auto whole = [](const std::string& t) {
    return !t.empty() && t.size() <= 9 && std::all_of(t.begin(), t.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (slash == std::string::npos || !whole(text.substr(0, slash)) || !whole(text.substr(slash + 1))) {
    throw bad("not K/N with whole numbers, K counted from 0 (0/4 .. 3/4)");
  }
  const std::size_t k = std::stoul(text.substr(0, slash)), n = std::stoul(text.substr(slash + 1));
  if (n == 0) throw bad("N must be at least 1");
  if (k >= n) throw bad("K must be below N (shards are counted from 0: 0.." + std::to_string(n - 1) + ")");
  return {k, n};
}

}  // namespace

void writeReport(json& j, const ValidateCommandOptions& options, const json& old, const std::vector<std::string>& images) {
  bool pass = true;  // every crack-free case keeps every guarantee (ValidationReport::pass)
  for (const json& c : j["cases"]) {
    if (c["method"] == "crackfree" && !c["pass"].get<bool>()) pass = false;
  }
  j["verdict"] = pass ? "PASS" : "FAIL";
  j["images"] = images;
  if (!options.compare.empty()) {
    j["compared_with"] = options.compare;
    j["regressions"] = compareReports(j, old);
  }
  geometry::writeFileAtomically(options.outDir + "/report.json", j.dump(2) + "\n");
  writeHtml(options.outDir + "/report.html", j, images);
}

int printVerdict(const json& j, const std::string& outDir) {
  std::cout << "verdict: " << j["verdict"].get<std::string>() << " (" << j["cases"].size() << " cases, "
            << j["regressions"].size() << " regressions, " << j["seconds"].get<double>()
            << " s); report: " << outDir << "/report.html\n";
  return j["verdict"] == "PASS" ? kExitOk : kExitCheckFailed;
}


int runValidate(const ValidateCommandOptions& options) {
  if (!options.merge.empty()) return runValidateMerge(options);
  options.source.check();  // the models' units or scale, before any work
  // Plain values, not an optional pair: GCC's -Wmaybe-uninitialized misreads the latter.
  const bool sharded = !options.shard.empty();
  const auto [shardIndex, shardCount] = sharded ? parseShard(options.shard) : std::pair<std::size_t, std::size_t>{0, 1};
  // Sizes given with --quick replace its 1.2 mm; given or not, they are checked.
  const std::vector<double> parsedSizes = parseVoxelSizes(options.voxelSizes);
  const std::vector<double> sizes =
      options.quick && !options.voxelSizesGiven ? std::vector<double>{1.2} : parsedSizes;
  const std::vector<std::string> names = splitList(options.models);
  if (names.empty()) throw InputError("--models " + options.models + ": no model given");
  const json old = options.compare.empty() ? json() : readComparable(options.compare);
  std::vector<std::string> inputs;
  for (const std::string& name : names) {
    BoneSource model = options.source;
    model.input = name;
    for (const std::string& file : model.inputFiles()) inputs.push_back(file);
  }
  inputs.push_back(options.compare);
  const std::string reportJsonPath = options.outDir + "/report.json";
  const std::string reportHtmlPath = options.outDir + "/report.html";
  const std::string logPath = options.outDir + "/validate.log";
  geometry::refuseOverwritingInputs({reportJsonPath, reportHtmlPath, logPath}, inputs);
  for (const char* owned : {"/forces", "/plots", "/images"}) refuseInputsInside(options.outDir + owned, inputs);
  // The report, the log, the force logs, plots and images are one set, put in place together
  // when the run is complete (output_dir.h).
  geometry::OutputDir outDir(options.outDir, {"report.json", "report.html", "validate.log", "forces", "plots", "images"});
  std::error_code ec;
  std::filesystem::create_directories(options.outDir + "/images", ec);
  if (ec) throw InputError("--out-dir " + options.outDir + ": cannot create the folder (" + ec.message() + ")");
  const std::map<std::string, std::string> fileNameOf = modelFileNames(names);
  std::vector<val::ValidationModel> models;
  for (const std::string& name : names) {
    BoneSource model = options.source;
    model.input = name;
    models.emplace_back();
    models.back().name = name;
    if (model.isVolume()) {
      // Its own voxel size, every non-background label or 300 HU (`osteon mesh VOLUME` says what it holds).
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
  // A shard runs the case groups assigned to it (shard.h); every shard computes the same split.
  const std::vector<val::CaseGroup> groups = val::caseGroups(models, vo);
  std::vector<bool> ownGroup(groups.size(), true);
  const std::vector<std::string> runKeys = val::caseKeys(models, groups);
  if (sharded) {
    // A merge finds each case by its key, so a model or voxel size given twice cannot be split.
    std::set<std::string> unique;
    for (const std::string& key : runKeys) {
      if (!unique.insert(key).second) {
        throw InputError("--shard " + options.shard + ": case " + key + " comes twice (a model or voxel size given twice)");
      }
    }
    std::vector<double> costs;
    for (const val::CaseGroup& g : groups) costs.push_back(g.cost);
    const std::vector<std::size_t> shardOf = val::assignShards(costs, shardCount);
    vo.groups.emplace();
    for (std::size_t g = 0; g < groups.size(); ++g) {
      ownGroup[g] = shardOf[g] == shardIndex;
      if (ownGroup[g]) vo.groups->push_back(g);
    }
  }
  std::size_t done = 0;
  const std::size_t total = static_cast<std::size_t>(std::count(ownGroup.begin(), ownGroup.end(), true)) *
                            val::kCasesPerGroup;
  // Force logs of the crack-free runs, for the plots: forces/<model>_<voxel>_<mode>_<portal>.csv.
  std::filesystem::create_directories(options.outDir + "/forces");
  std::map<std::string, std::vector<ForceSeries>> plotGroups;  // model, voxel size, portal -> runs
  const val::ValidationReport report = val::runValidation(models, vo, [&](const val::ValidationCase& c) {
    throwIfInterrupted();  // a case cut short by SIGINT/SIGTERM: the run ends, nothing put in place
    if (c.method == geometry::SurfaceMethod::CrackFree) {
      for (const val::PortalRun& p : c.portals) {
        std::ostringstream stem, group;
        stem << "forces/" << fileNameOf.at(c.model) << "_" << c.voxelSizeMm << "mm_" << val::forceModeName(c.mode)
             << "_" << p.portal << ".csv";
        group << fileNameOf.at(c.model) << ", VS = " << c.voxelSizeMm << " mm, " << p.portal;
        simulation::writeForceLog(p.collisions.run.log, options.outDir + "/" + stem.str());
        std::ostringstream label;
        const bool still = c.mode == val::ForceMode::Static;
        label << val::forceModeName(c.mode) << (still ? " " : " 2 levels, ") << c.voxelSizeMm / (still ? 1.0 : 4.0)
              << " mm";
        plotGroups[group.str()].push_back({options.outDir + "/" + stem.str(), label.str(), still ? 1.2 : 1.6});
      }
    }
    std::ostringstream line;
    line << "[" << ++done << "/" << total << "] " << c.model << " " << c.voxelSizeMm << " mm " << geometry::surfaceMethodName(c.method) << " "
         << val::forceModeName(c.mode) << ": ";
    if (c.method == geometry::SurfaceMethod::Naive) {
      line << (c.pass() ? "baseline keeps the guarantees (unexpected)" : "baseline breaks the guarantees, as expected");
    } else {
      line << (c.pass() ? "pass" : "FAIL");
    }
    for (const std::string& f : c.failures) line << "; " << f;
    std::cout << line.str() << "\n" << std::flush;
    log << line.str() << "\n" << std::flush;
  });

  // Crack views of each model's surfaces at the first voxel size, before drilling; in a shard,
  // of the models whose first group it runs.
  std::vector<bool> ownImages(models.size(), false);
  for (std::size_t g = groups.size(); g-- > 0;) ownImages[groups[g].model] = ownGroup[g];
  std::vector<std::string> images;
  for (const val::ValidationModel& m : models) {
    if (!ownImages[static_cast<std::size_t>(&m - models.data())]) continue;
    geometry::VoxelizeOptions gv;
    gv.voxelSizeMm = sizes.front();
    gv.requireInside = true;
    gv.meshName = m.name;
    gv.loadScaleToMm = m.loadScaleToMm;
    const geometry::VoxelGrid grid = m.volume ? *m.volume : geometry::voxelize(m.mesh, gv);
    for (const char* method : {"crackfree", "naive"}) {
      geometry::SurfaceOptions so;
      so.method = std::string(method) == "naive" ? geometry::SurfaceMethod::Naive : geometry::SurfaceMethod::CrackFree;
      val::CrackMetricOptions co;
      co.pixels = 256;
      co.keepImages = true;
      const std::string dir = options.outDir + "/images/" + std::to_string(&m - models.data()) + "_" + method;
      std::filesystem::create_directories(dir);
      for (const std::string& p : val::writeCrackImages(val::measureCracks(geometry::extractSurface(grid, so).toTriangleMesh(), co), dir)) {
        images.push_back(std::filesystem::relative(p, options.outDir).string());
      }
    }
  }

  // Static against dynamic per model, voxel size and portal, as the seed's Figs. 6-8.
  std::vector<ForceFigure> figures;
  std::vector<std::string> plots;
  std::filesystem::create_directories(options.outDir + "/plots");
  for (const auto& [group, series] : plotGroups) {
    std::string name;  // the title, as a file name
    for (const char ch : group) {
      if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-') name += ch;
      else if (!name.empty() && name.back() != '_') name += '_';
    }
    figures.push_back({options.outDir + "/plots/" + name + ".png", group + ": static and dynamic voxels", series});
    plots.push_back("plots/" + name + ".png");
  }
  if (!figures.empty()) drawForcePlots(figures, options.outDir + "/plots/plots.gp");
  std::sort(plots.begin(), plots.end());  // as a merge lists the shards' plots

  json cases = json::array();
  for (const val::ValidationCase& c : report.cases) cases.push_back(caseJson(c));
  const double seconds = std::chrono::duration<double>(std::chrono::system_clock::now() - started).count();
  json j = {{"schema", "osteon-validate/1"},
            {"started", startedText},
            {"seconds", seconds},
            {"osteon_version", OSTEON_VERSION},
            {"options", {{"models", names}, {"voxel_sizes_mm", sizes}, {"quick", options.quick},
                         {"crack_pixels", vo.crackPixels}, {"collision_check_every_steps", vo.checkEverySteps}}},
            {"environment", environmentJson()},
            {"cases", cases},
            {"plots", plots},
            {"regressions", json::array()}};
  if (sharded) {
    // The whole run's case list, so a merge can tell shards of one run from shards of another.
    const std::vector<std::string>& keys = runKeys;
    json own = json::array();
    double cost = 0.0, totalCost = 0.0;
    for (std::size_t g = 0; g < groups.size(); ++g) {
      totalCost += groups[g].cost;
      if (!ownGroup[g]) continue;
      cost += groups[g].cost;
      for (int k = 0; k < val::kCasesPerGroup; ++k) own.push_back(keys[g * val::kCasesPerGroup + k]);
    }
    j["shard"] = {{"index", shardIndex}, {"count", shardCount}, {"case_list", keys}, {"cases", own},
                  {"estimated_cost", cost}, {"run_estimated_cost", totalCost}};
  }
  writeReport(j, options, old, images);
  log.close();
  if (!log) throw InputError(logPath + ": writing failed (disk full or not writable?)");
  logFile.commit();
  outDir.commit();
  return printVerdict(j, options.outDir);
}

}  // namespace osteon::cli
