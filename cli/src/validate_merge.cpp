// `osteon validate --merge`: the reports of a run's shards (`--shard K/N`) as the one report
// the whole run writes, after checking that they are one run.
#include "validate_report.h"

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace osteon::cli {

using nlohmann::json;

namespace {

// Crack images sort by the model index that leads their folder (images/<model>_<method>/), as
// a whole run writes them; a shard writes those of the models whose first group it owns.
std::size_t imageModelIndex(const std::string& image) {
  const std::string prefix = "images/";
  if (image.rfind(prefix, 0) != 0) return 0;
  std::size_t i = prefix.size(), index = 0;
  while (i < image.size() && std::isdigit(static_cast<unsigned char>(image[i]))) index = index * 10 + (image[i++] - '0');
  return index;
}

// The first field of a case that the merge and report.html read and that is missing or of
// the wrong type, or "" when there is none: a merged report is only as sound as its shards'.
std::string caseFieldMissing(const json& c) {
  if (!c.is_object()) return "not an object";
  for (const char* k : {"model", "method", "mode"}) {
    if (!c.value(k, json()).is_string()) return std::string("\"") + k + "\" is not a string";
  }
  if (!c.value("pass", json()).is_boolean()) return "\"pass\" is not true or false";
  const json failures = c.value("failures", json());
  if (!failures.is_array() || !std::all_of(failures.begin(), failures.end(), [](const json& f) { return f.is_string(); })) {
    return "\"failures\" is not a list of strings";
  }
  for (const char* k : {"voxel_size_mm", "border_edges", "non_manifold", "self_intersections", "crack_percent",
                        "collision_misses", "collision_missed_samples", "collision_rays", "max_force_n", "jitter_n",
                        "voxels", "triangles", "vertices"}) {
    if (!c.value(k, json()).is_number()) return std::string("\"") + k + "\" is not a number";
  }
  const json hausdorff = c.value("hausdorff_mm", json(false));
  if (!hausdorff.is_number() && !hausdorff.is_null()) return "\"hausdorff_mm\" is not a number or null";
  const json times = c.value("mesh_time_ms", json());
  for (const char* k : {"total", "extract", "smooth", "normals", "other"}) {
    if (!times.is_object() || !times.value(k, json()).is_number()) return std::string("\"mesh_time_ms\" has no ") + k;
  }
  if (c.contains("after")) {
    const json& after = c["after"];
    if (!after.is_object() || !after.value("border_edges", json()).is_number() ||
        !after.value("crack_percent", json()).is_number()) {
      return "\"after\" has no border_edges or crack_percent";
    }
  }
  return "";
}

struct ShardReport {
  std::string dir;
  json report;
  std::size_t index = 0, count = 0;
};

// One shard's report.json, checked for what a merge relies on.
ShardReport readShard(const std::string& dir) {
  const std::string path = dir + "/report.json";
  const auto bad = [&](const std::string& why) { return InputError("--merge " + dir + ": " + why); };
  std::ifstream in(path);
  if (!in) throw bad("no report.json to read (cannot open " + path + ")");
  ShardReport s;
  s.dir = dir;
  try {
    s.report = json::parse(in);
  } catch (const std::exception&) {
    throw bad("report.json is not JSON (truncated or not a validate report)");
  }
  const json& r = s.report;
  if (!r.is_object() || r.value("schema", json()) != "osteon-validate/1") {
    throw bad("report.json is not a validate report (no \"schema\": \"osteon-validate/1\")");
  }
  if (!r.contains("shard") || !r["shard"].is_object()) {
    throw bad("not a shard report (no \"shard\" object: written by validate --shard K/N)");
  }
  const json& sh = r["shard"];
  const auto strings = [](const json& a) {
    return a.is_array() && std::all_of(a.begin(), a.end(), [](const json& x) { return x.is_string(); });
  };
  if (!sh.value("index", json()).is_number_unsigned() || !sh.value("count", json()).is_number_unsigned() ||
      !strings(sh.value("case_list", json())) || !strings(sh.value("cases", json()))) {
    throw bad("not a shard report (\"shard\" needs index, count, case_list and cases)");
  }
  s.index = sh["index"].get<std::size_t>();
  s.count = sh["count"].get<std::size_t>();
  if (s.count == 0 || s.index >= s.count) throw bad("not a shard report (shard " + sh["index"].dump() + "/" + sh["count"].dump() + ")");
  for (const char* k : {"osteon_version", "started"}) {
    if (!r.value(k, json()).is_string()) throw bad(std::string("not a shard report (\"") + k + "\" is not a string)");
  }
  if (!r.value("seconds", json()).is_number() || !r.contains("options") || !strings(r.value("plots", json())) ||
      !strings(r.value("images", json())) || !r.value("cases", json()).is_array()) {
    throw bad("not a shard report (seconds, options, plots, images or cases missing)");
  }
  // Its cases must be those its shard object names, in that order (a hand-edited or truncated
  // report would otherwise merge silently).
  const json& cases = r["cases"];
  if (cases.size() != sh["cases"].size()) throw bad("report.json holds " + std::to_string(cases.size()) +
                                                    " cases, its shard names " + std::to_string(sh["cases"].size()));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string what = caseFieldMissing(cases[i]);
    if (!what.empty()) throw bad("case " + std::to_string(i) + " is not a validate case (" + what + ")");
    if (caseKey(cases[i]) != sh["cases"][i]) {
      throw bad("case " + std::to_string(i) + " is not the case its shard names (" + sh["cases"][i].get<std::string>() + ")");
    }
  }
  return s;
}

// Copies a shard's images, plots and force logs into the merged report's folder, so it stands
// alone; not the shard's gnuplot script, which names the shard's own files.
void copyShardFiles(const std::string& fromDir, const std::string& toDir) {
  namespace fs = std::filesystem;
  for (const char* sub : {"images", "plots", "forces"}) {
    std::error_code ec;
    if (!fs::is_directory(fromDir + "/" + sub, ec)) continue;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(fromDir + "/" + sub, ec)) {
      const std::string name = e.path().filename().string();
      if (!e.is_regular_file() || name.rfind("plots.gp", 0) == 0) continue;
      const fs::path to = fs::path(toDir) / fs::relative(e.path(), fromDir);
      fs::create_directories(to.parent_path(), ec);
      if (!ec) geometry::copyFileAtomically(e.path().string(), to.string());  // with the run's set
      if (ec) throw InputError("--out-dir " + toDir + ": cannot copy " + e.path().string() + " (" + ec.message() + ")");
    }
    if (ec) throw InputError("--merge " + fromDir + ": cannot read " + sub + " (" + ec.message() + ")");
  }
}

// --merge: the shards' reports as one, as the whole run would have written it.
}  // namespace

int runValidateMerge(const ValidateCommandOptions& options) {
  namespace fs = std::filesystem;
  if (!options.runOptionsGiven.empty()) {
    throw InputError("--merge: " + options.runOptionsGiven.front() +
                     " is an option of a run, not of a merge (each shard's report holds its run's options)");
  }
  const json old = options.compare.empty() ? json() : readComparable(options.compare);
  std::vector<ShardReport> shards;
  for (const std::string& dir : options.merge) shards.push_back(readShard(dir));

  // One run: the same osteon, options, shard count and case list in every report.
  const ShardReport& first = shards.front();
  for (const ShardReport& s : shards) {
    const std::string pair = first.dir + " and " + s.dir;
    if (s.report["osteon_version"] != first.report["osteon_version"]) {
      throw InputError("--merge: " + pair + " come from different osteon versions (" +
                       first.report["osteon_version"].get<std::string>() + ", " +
                       s.report["osteon_version"].get<std::string>() + ")");
    }
    if (s.count != first.count) {
      throw InputError("--merge: " + pair + " are shards of different splits (of " + std::to_string(first.count) +
                       " and of " + std::to_string(s.count) + " shards)");
    }
    if (s.report["shard"]["case_list"] != first.report["shard"]["case_list"]) {
      throw InputError("--merge: " + pair + " are shards of different runs (their case lists differ)");
    }
    if (s.report["options"] != first.report["options"]) {
      throw InputError("--merge: " + pair + " are shards of different runs (their options differ)");
    }
  }
  std::vector<const ShardReport*> byIndex(first.count, nullptr);
  for (const ShardReport& s : shards) {
    const ShardReport*& slot = byIndex[s.index];
    if (slot) {
      throw InputError("--merge: " + slot->dir + " and " + s.dir + " are both shard " + std::to_string(s.index) + "/" +
                       std::to_string(s.count));
    }
    slot = &s;
  }
  std::string missing;
  for (std::size_t k = 0; k < byIndex.size(); ++k) {
    if (!byIndex[k]) missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(first.count);
  }
  if (!missing.empty()) {
    std::string given;
    for (const ShardReport& s : shards) {
      given += (given.empty() ? "" : ", ") + s.dir + " (" + std::to_string(s.index) + "/" + std::to_string(s.count) + ")";
    }
    throw InputError("--merge: shard " + missing + " missing (given: " + given + ")");
  }

  // Every case of the run in exactly one shard, then in the run's order.
  std::map<std::string, const json*> caseOf;
  std::map<std::string, std::string> dirOf;
  for (const ShardReport& s : shards) {
    for (const json& c : s.report["cases"]) {
      const std::string key = caseKey(c);
      if (caseOf.count(key)) throw InputError("--merge: " + dirOf[key] + " and " + s.dir + " both hold case " + key);
      caseOf[key] = &c;
      dirOf[key] = s.dir;
    }
  }
  json cases = json::array();
  for (const json& key : first.report["shard"]["case_list"]) {
    const auto it = caseOf.find(key.get<std::string>());
    if (it == caseOf.end()) throw InputError("--merge: no shard holds case " + key.get<std::string>());
    cases.push_back(*it->second);
  }
  if (cases.size() != caseOf.size()) throw InputError("--merge: a shard holds a case outside its run's case list");

  // Outputs: never into a shard's own folder, never over an input.
  std::vector<std::string> inputs{options.compare};
  for (const ShardReport& s : shards) {
    std::error_code ec;
    if (fs::exists(options.outDir, ec) && fs::equivalent(options.outDir, s.dir, ec)) {
      throw InputError("--out-dir " + options.outDir + ": is the shard folder " + s.dir +
                       " (merge into another folder)");
    }
    inputs.push_back(s.dir + "/report.json");
  }
  geometry::refuseOverwritingInputs({options.outDir + "/report.json", options.outDir + "/report.html",
                                     options.outDir + "/validate.log"}, inputs);
  for (const char* owned : {"/forces", "/plots", "/images"}) refuseInputsInside(options.outDir + owned, inputs);
  geometry::OutputDir outDir(options.outDir, {"report.json", "report.html", "validate.log", "forces", "plots", "images"});

  std::set<std::string> plots;
  std::vector<std::string> images;
  std::string log;
  json mergedFrom = json::array(), shardSeconds = json::array();
  double seconds = 0.0;
  std::string started = byIndex.front()->report["started"];
  for (const ShardReport* s : byIndex) {
    copyShardFiles(s->dir, options.outDir);
    for (const json& p : s->report["plots"]) plots.insert(p.get<std::string>());
    for (const json& i : s->report["images"]) images.push_back(i.get<std::string>());
    mergedFrom.push_back(s->dir);
    shardSeconds.push_back(s->report["seconds"]);
    seconds += s->report["seconds"].get<double>();
    started = std::min(started, s->report["started"].get<std::string>());  // ISO 8601 UTC sorts as text
    std::ifstream shardLog(s->dir + "/validate.log");
    log += "# shard " + std::to_string(s->index) + "/" + std::to_string(s->count) + ": " + s->dir + "\n";
    log += std::string(std::istreambuf_iterator<char>(shardLog), std::istreambuf_iterator<char>());
  }
  std::stable_sort(images.begin(), images.end(),
                   [](const std::string& a, const std::string& b) { return imageModelIndex(a) < imageModelIndex(b); });
  geometry::writeFileAtomically(options.outDir + "/validate.log", log);
  json j = {{"schema", "osteon-validate/1"},
            {"started", started},
            {"seconds", seconds},
            {"osteon_version", first.report["osteon_version"]},
            {"options", first.report["options"]},
            {"environment", byIndex.front()->report.value("environment", json::object())},
            {"cases", cases},
            {"plots", std::vector<std::string>(plots.begin(), plots.end())},
            {"regressions", json::array()},
            {"merged_from", mergedFrom},
            {"shard_seconds", shardSeconds}};
  writeReport(j, options, old, images);
  outDir.commit();
  return printVerdict(j, options.outDir);
}


}  // namespace osteon::cli
