// Reading and checking validate reports for --compare and --merge (report_reader.h).
#include "report_reader.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include "osteon/core/error.h"
#include "osteon/validation/shard.h"

namespace osteon::cli {

using nlohmann::json;

namespace {

// What a field must hold. Counts are whole numbers that fit 64 bits; amounts are finite and
// not negative (JSON has no NaN or infinity, and nlohmann refuses numbers that overflow), or
// null where a run writes one: no Hausdorff distance for a volume, NaN forces (a failed case).
enum class Kind { Text, Flag, Texts, Count, AmountOrNull, Percent, VoxelSize, Millis, Seconds };

struct Field {
  const char* name;
  Kind kind;
};

// The fields a case is found by (caseKey), then those --compare compares, then the rest that
// a merge and report.html read.
constexpr Field kKeyFields[] = {{"model", Kind::Text},
                                {"voxel_size_mm", Kind::VoxelSize},
                                {"method", Kind::Text},
                                {"mode", Kind::Text}};
constexpr Field kComparedFields[] = {{"pass", Kind::Flag},
                                     {"border_edges", Kind::Count},
                                     {"non_manifold", Kind::Count},
                                     {"self_intersections", Kind::Count},
                                     {"collision_misses", Kind::Count},
                                     {"crack_percent", Kind::Percent},
                                     {"hausdorff_mm", Kind::AmountOrNull},
                                     {"jitter_n", Kind::AmountOrNull}};
constexpr Field kMergedFields[] = {
    {"failures", Kind::Texts},       {"collision_missed_samples", Kind::Count},
    {"collision_rays", Kind::Count}, {"max_force_n", Kind::AmountOrNull},
    {"voxels", Kind::Count},         {"triangles", Kind::Count},
    {"vertices", Kind::Count}};
constexpr const char* kMeshTimes[] = {"total", "extract", "smooth", "normals", "other"};
constexpr const char* kCaseTimes[] = {"setup", "surface", "drill"};

// A value as a message shows it: its JSON, cut short.
std::string shown(const json& v) {
  std::string text = v.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

// What is wrong with `v` as a `kind`, or "".
std::string problem(const json& v, Kind kind) {
  const auto range = [&](const char* want) { return "is " + shown(v) + ", not " + want; };
  switch (kind) {
    case Kind::Text:
      return v.is_string() ? "" : "is not a string (" + shown(v) + ")";
    case Kind::Flag:
      return v.is_boolean() ? "" : "is not true or false (" + shown(v) + ")";
    case Kind::Texts:
      return v.is_array() &&
                     std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_string(); })
                 ? ""
                 : "is not a list of strings (" + shown(v) + ")";
    default:
      break;
  }
  if (kind == Kind::AmountOrNull && v.is_null()) return "";
  if (!v.is_number()) return "is not a number (" + shown(v) + ")";
  if (kind == Kind::Count)
    return v.is_number_unsigned() ? "" : range("a whole count from 0 to 2^64-1");
  const double x = v.get<double>();
  if (!std::isfinite(x) || x < 0.0) return range("a finite number of at least 0");
  if (kind == Kind::Percent && x > 100.0) return range("a percentage of at most 100");
  if (kind == Kind::VoxelSize && x <= 0.0) return range("a voxel size above 0 mm");
  if (kind == Kind::Millis && x > kMaxRunSeconds * 1000.0)
    return range("a time a run can take (at most a year)");
  if (kind == Kind::Seconds && x > kMaxRunSeconds)
    return range("a time a run can take (at most a year)");
  return "";
}

// Checks `fields` of `object`; a missing field is an error only when `required`. Returns the
// first problem as "\"name\" <what>", or "".
template <std::size_t N>
std::string fieldsProblem(const json& object, const Field (&fields)[N], bool required,
                          const std::string& prefix = "") {
  for (const Field& f : fields) {
    const auto it = object.find(f.name);
    if (it == object.end()) {
      if (required) return "\"" + prefix + f.name + "\" is missing";
      continue;
    }
    const std::string what = problem(*it, f.kind);
    if (!what.empty()) return "\"" + prefix + f.name + "\" " + what;
  }
  return "";
}

// Timings kept in an object ("mesh_time_ms": {"total": ...}), every one a plausible time.
std::string timesProblem(const json& c, const char* name, const char* const* keys,
                         std::size_t count, bool required) {
  const auto it = c.find(name);
  if (it == c.end()) return required ? std::string("\"") + name + "\" is missing" : "";
  if (!it->is_object())
    return std::string("\"") + name + "\" is not an object (" + shown(*it) + ")";
  for (std::size_t i = 0; i < count; ++i) {
    const auto t = it->find(keys[i]);
    if (t == it->end()) return std::string("\"") + name + "\" has no " + keys[i];
    const std::string what = problem(*t, Kind::Millis);
    if (!what.empty()) return std::string("\"") + name + "." + keys[i] + "\" " + what;
  }
  return "";
}

// The first problem of a case, or "": a comparable case (`merged` false) needs only its key
// fields, the compared ones where present; a shard's case everything a merge reads.
std::string caseProblem(const json& c, bool merged) {
  if (!c.is_object()) return "is not an object (" + shown(c) + ")";
  std::string what = fieldsProblem(c, kKeyFields, merged);
  if (what.empty()) what = fieldsProblem(c, kComparedFields, merged);
  if (what.empty() && merged) what = fieldsProblem(c, kMergedFields, true);
  if (what.empty())
    what = timesProblem(c, "mesh_time_ms", kMeshTimes, std::size(kMeshTimes), merged);
  if (what.empty()) what = timesProblem(c, "case_ms", kCaseTimes, std::size(kCaseTimes), false);
  if (what.empty() && c.contains("extract_ms")) {
    const std::string t = problem(c["extract_ms"], Kind::Millis);
    if (!t.empty()) what = "\"extract_ms\" " + t;
  }
  if (what.empty() && c.contains("after")) {
    const json& after = c["after"];
    if (!after.is_object()) return "\"after\" is not an object (" + shown(after) + ")";
    constexpr Field kAfter[] = {{"border_edges", Kind::Count}, {"crack_percent", Kind::Percent}};
    what = fieldsProblem(after, kAfter, merged, "after.");
  }
  return what;
}

// "case 3 (default|1.2|crackfree|static)", or "case 3" while its key fields are in doubt.
std::string caseName(const json& c, std::size_t i) {
  std::string name = "case " + std::to_string(i);
  if (c.is_object() && fieldsProblem(c, kKeyFields, true).empty()) name += " (" + caseKey(c) + ")";
  return name;
}

bool isPlainName(const std::string& name) {
  if (name.empty() || name.front() == '.' || name.size() > 255) return false;
  return std::all_of(name.begin(), name.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '+' ||
           ch == '.';
  });
}

struct TooDeep {};

// The report written names this path (compared_with, merged_from), and JSON text is UTF-8:
// refused up front rather than failing the dump after the work.
void requireUtf8Name(const std::string& path, const std::string& what) {
  try {
    (void)json(path).dump();
  } catch (const json::type_error&) {
    throw InputError(what + ": the name is not UTF-8 text, which report.json must record it as");
  }
}

}  // namespace

json readReportJson(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  const std::string name = fs::path(path).filename().string();
  // "--compare OLD.json: is not JSON", but "--merge DIR: report.json is not JSON".
  const bool named =
      what.size() >= path.size() && what.compare(what.size() - path.size(), path.size(), path) == 0;
  const std::string it = named ? what + ": " : what + ": " + name + " ";
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    throw InputError(it + "is not a regular file (a report is a file validate wrote)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(what + ": no " + name + " to read (cannot open " + path + ": " +
                     std::strerror(errno) + ")");
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (!ec && bytes > kMaxReportBytes) {
    throw InputError(it + "is " + std::to_string(bytes >> 20) +
                     " MiB, larger than any validate report (at most " +
                     std::to_string(kMaxReportBytes >> 20) + " MiB)");
  }
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  // The parser itself loops; nlohmann's copy, compare and dump recurse. A container is refused
  // as it opens, so nothing deeper than the limit is ever built.
  const auto bounded = [](int depth, json::parse_event_t event, json&) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
        depth >= kMaxReportDepth) {
      throw TooDeep{};
    }
    return true;
  };
  try {
    return json::parse(text, bounded);
  } catch (const TooDeep&) {
    throw InputError(it + "nests deeper than " + std::to_string(kMaxReportDepth) +
                     " levels (a validate report nests 5): not a validate report");
  } catch (const json::parse_error& e) {
    throw InputError(it + "is not JSON (error at byte " + std::to_string(e.byte) +
                     ": truncated, or not a validate report)");
  } catch (const json::exception& e) {
    throw InputError(it + "is not JSON (" + e.what() + ")");
  }
}

std::string caseKey(const json& c) {
  return validation::caseKey(c.value("model", ""), c.value("voxel_size_mm", 0.0),
                             c.value("method", ""), c.value("mode", ""));
}

json readComparable(const std::string& path) {
  const std::string what = "--compare " + path;
  requireUtf8Name(path, what);
  json old = readReportJson(path, what);
  const auto bad = [&](const std::string& why) { return InputError(what + ": " + why); };
  if (!old.is_object())
    throw bad(std::string("not a validate report (a JSON ") + old.type_name() + ", not an object)");
  if (!old.contains("schema") || old["schema"] != "osteon-validate/1") {
    throw bad("not a validate report (no \"schema\": \"osteon-validate/1\")");
  }
  if (!old.contains("cases") || !old["cases"].is_array())
    throw bad("\"cases\" is missing or not an array");
  for (std::size_t i = 0; i < old["cases"].size(); ++i) {
    const json& c = old["cases"][i];
    const std::string problem = caseProblem(c, false);
    if (!problem.empty()) throw bad(caseName(c, i) + ": " + problem);
  }
  return old;
}

bool isReportOutputPath(const std::string& path, const std::string& folder) {
  if (path.rfind(folder + "/", 0) != 0) return false;
  std::size_t start = folder.size() + 1;
  for (;;) {
    const std::size_t slash = path.find('/', start);
    if (!isPlainName(
            path.substr(start, slash == std::string::npos ? std::string::npos : slash - start)))
      return false;
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

ShardReport readShard(const std::string& dir, const std::string& reportPath) {
  const std::string what = "--merge " + dir;
  const auto bad = [&](const std::string& why) { return InputError(what + ": " + why); };
  requireUtf8Name(dir, what);
  ShardReport s;
  s.dir = dir;
  s.report = readReportJson(reportPath, what);
  const json& r = s.report;
  if (!r.is_object() || r.value("schema", json()) != "osteon-validate/1") {
    throw bad("report.json is not a validate report (no \"schema\": \"osteon-validate/1\")");
  }
  if (!r.contains("shard") || !r["shard"].is_object()) {
    throw bad("not a shard report (no \"shard\" object: written by validate --shard K/N)");
  }
  const json& sh = r["shard"];
  const auto strings = [](const json& a) { return problem(a, Kind::Texts).empty(); };
  if (!sh.value("index", json()).is_number_unsigned() ||
      !sh.value("count", json()).is_number_unsigned() || !strings(sh.value("case_list", json())) ||
      !strings(sh.value("cases", json()))) {
    throw bad("not a shard report (\"shard\" needs index, count, case_list and cases)");
  }
  s.index = sh["index"].get<std::size_t>();
  s.count = sh["count"].get<std::size_t>();
  // --shard takes N of at most 9 digits; a merge needs every shard given, so N stays small.
  if (s.count == 0 || s.count > 999999999 || s.index >= s.count) {
    throw bad("not a shard report (shard " + shown(sh["index"]) + "/" + shown(sh["count"]) + ")");
  }
  // validate refuses a run without models, and every model at every size makes cases: a run
  // with no cases is not one validate made, and must not merge into a PASS.
  if (sh["case_list"].empty())
    throw bad("its run has no cases (\"case_list\" is empty): nothing to merge");
  for (const char* k : {"osteon_version", "started"}) {
    if (!r.value(k, json()).is_string())
      throw bad(std::string("not a shard report (\"") + k + "\" is not a string)");
  }
  if (!r.contains("seconds") || !r.contains("options") || !strings(r.value("plots", json())) ||
      !strings(r.value("images", json())) || !r.value("cases", json()).is_array()) {
    throw bad("not a shard report (seconds, options, plots, images or cases missing)");
  }
  const std::string seconds = problem(r["seconds"], Kind::Seconds);
  if (!seconds.empty()) throw bad("\"seconds\" " + seconds);
  // report.html shows what a report lists, and the merge's folder holds them: plain names only.
  for (const char* folder : {"images", "plots"}) {
    for (const json& p : r[folder]) {
      if (!isReportOutputPath(p.get<std::string>(), folder)) {
        throw bad(std::string("\"") + folder + "\" lists " + shown(p) + ", not a file under " +
                  folder + "/ of plain names (letters, digits, _ - + .)");
      }
    }
  }
  // Its cases must be those its shard object names, in that order (a hand-edited or truncated
  // report would otherwise merge silently).
  const json& cases = r["cases"];
  if (cases.size() != sh["cases"].size()) {
    throw bad("report.json holds " + std::to_string(cases.size()) + " cases, its shard names " +
              std::to_string(sh["cases"].size()));
  }
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string problem = caseProblem(cases[i], true);
    if (!problem.empty())
      throw bad(caseName(cases[i], i) + " is not a validate case (" + problem + ")");
    if (caseKey(cases[i]) != sh["cases"][i]) {
      throw bad("case " + std::to_string(i) + " is not the case its shard names (" +
                sh["cases"][i].get<std::string>() + ")");
    }
  }
  return s;
}

}  // namespace osteon::cli
