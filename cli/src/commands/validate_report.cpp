// report.json and report.html of `osteon validate` (a run or a merge of shards): the cases as
// JSON, the environment, regressions against an older report, the HTML page.
#include "commands/validate_report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <sys/utsname.h>
#include <thread>

#include "osteon/core/error.h"
#include "osteon/geometry/io/library_versions.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/validation/library_versions.h"

namespace osteon::cli {

using nlohmann::json;
namespace val = osteon::validation;

namespace {

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

}  // namespace

json caseJson(const val::ValidationCase& c) {
  std::uint64_t misses = 0, falseContacts = 0, checked = 0, nonFinite = 0, rays = 0,
                missedSamples = 0;
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
    portals.push_back({{"portal", p.portal},
                       {"collision_misses", p.collisions.misses},
                       {"false_contacts", p.collisions.falseContacts},
                       {"checked_steps", p.collisions.checked},
                       {"contacts", p.collisions.contacts},
                       {"contact_samples", p.collisions.contactSamples},
                       {"boundary_samples", p.collisions.boundarySamples},
                       {"skipped_samples", p.collisions.skippedSamples},
                       {"skipped_steps", p.collisions.skippedSteps},
                       {"rays_cast", p.collisions.raysCast},
                       {"missed_samples", p.collisions.missedSamples},
                       {"worst_miss_mm", p.collisions.worstMissMm},
                       {"max_force_n", p.maxForceN},
                       {"jitter_n", p.jitterN},
                       {"removed_volume_mm3", p.collisions.run.summary.removedVolumeMm3}});
  }
  json j = {
      {"model", c.model},
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
      {"hausdorff_voxels",
       c.accuracyKnown ? json(c.accuracy.hausdorffMm / c.voxelSizeMm) : json(nullptr)},
      {"volume_difference_percent",
       c.accuracyKnown ? json(c.accuracy.volumeDifferencePercent) : json(nullptr)},
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
      {"mesh_time_ms",
       {{"total", c.timings.totalMs},
        {"extract", c.timings.extractMs},
        {"smooth", c.timings.smoothMs},
        {"normals", c.timings.normalsMs},
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
    const std::size_t start =
        colon == std::string::npos ? colon : line.find_first_not_of(" \t", colon + 1);
    if (start != std::string::npos) cpu = line.substr(start);
    break;
  }
  const std::string buildType = OSTEON_BUILD_TYPE;
  return {{"compiler", __VERSION__},
          {"cpp", __cplusplus},
          {"build_type", buildType.empty() ? "unset" : buildType},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"os", os},
          {"cpu", cpu},
          {"libraries", libraries}};
}

// Regressions against an older report: a case that passed and fails, or a crack-free metric
// that got worse (counts up at all; distances and jitter by more than 10 %).
namespace {

json compareReports(const json& now, const json& old) {
  std::map<std::string, const json*> before;
  for (const json& c : old["cases"]) before[caseKey(c)] = &c;
  json regressions = json::array();
  for (const json& c : now["cases"]) {
    const auto it = before.find(caseKey(c));
    if (it == before.end()) continue;
    const json& o = *it->second;
    const auto note = [&](const std::string& what) {
      regressions.push_back({{"case", caseKey(c)}, {"what", what}});
    };
    if (o.value("pass", false) && !c.value("pass", false)) note("passed before, fails now");
    if (c.value("method", "") != "crackfree") continue;
    // Both reports are checked (readComparable, readShard, or written here): a count is a whole
    // number of 64 bits, a distance a finite number; a field the old report lacks is not compared.
    for (const char* k :
         {"border_edges", "non_manifold", "self_intersections", "collision_misses"}) {
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
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      case '`':
        out += "&#96;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string htmlEscape(const json& v) {
  return htmlEscape(v.is_string() ? v.get<std::string>() : v.dump());
}

// A number for a table cell: four significant digits (the JSON keeps full precision).
std::string cell(const json& v) {
  if (!v.is_number_float()) return htmlEscape(v);
  std::ostringstream out;
  out << std::setprecision(4) << v.get<double>();
  return out.str();
}

void writeHtml(const std::string& path, const json& report,
               const std::vector<std::string>& images) {
  std::ostringstream h;
  const bool pass = report["verdict"] == "PASS";
  const std::string verdict = htmlEscape(report["verdict"]);
  h << "<!doctype html><html><head><meta charset=\"utf-8\"><title>osteon validation: " << verdict
    << "</title><style>body{font-family:sans-serif;margin:2em}"
    << "table{border-collapse:collapse}td,th{border:1px solid #999;padding:3px "
       "8px;text-align:right}"
    << ".pass{color:#070}.fail{color:#b00;font-weight:bold}img{width:200px;margin:4px;border:1px "
       "solid #ccc}</style>"
    << "</head><body>\n<h1>osteon validation: <span class=\"" << (pass ? "pass" : "fail") << "\">"
    << verdict << "</span></h1>\n<p>"
    << (pass ? "Every crack-free case keeps every guarantee."
             : "A crack-free case broke a guarantee: see the failures below.")
    << " The naive method is the seed's baseline, measured beside it and expected to fail.</p>\n";
  h << "<p>Started " << htmlEscape(report["started"]) << ", " << report["seconds"].get<double>()
    << " s. osteon " << htmlEscape(report["osteon_version"]) << ".</p>\n";
  if (report.contains("shard")) {
    const json& shard = report["shard"];
    h << "<p>Shard " << htmlEscape(shard["index"]) << " of " << htmlEscape(shard["count"])
      << " (counted from 0): " << shard["cases"].size() << " of the run's "
      << shard["case_list"].size() << " cases; merge the shards with "
      << "<code>osteon validate --merge</code>.</p>\n";
  }
  if (report.contains("merged_from")) {
    h << "<p>Merged from " << report["merged_from"].size()
      << " shards (the seconds above are their sum):";
    for (const json& d : report["merged_from"]) h << " " << htmlEscape(d);
    h << ".</p>\n";
  }
  if (!report["regressions"].empty()) {
    h << "<h2 class=\"fail\">Regressions against " << htmlEscape(report.value("compared_with", ""))
      << "</h2><ul>";
    for (const json& r : report["regressions"])
      h << "<li>" << htmlEscape(r["case"]) << ": " << htmlEscape(r["what"]) << "</li>";
    h << "</ul>\n";
  }
  h << "<h2>Cases</h2><table><tr><th>model</th><th>voxel</th><th>method</th><th>mode</"
       "th><th>verdict</th>"
    << "<th>border edges</th><th>non-manifold</th><th>self-int.</th><th>cracks %</th><th>Hausdorff "
       "mm</th>"
    << "<th>collision misses</th><th>rays missed / cast</th><th>max |F| N</th><th>jitter "
       "N</th><th>after drilling: border / cracks %</th></tr>\n";
  for (const json& c : report["cases"]) {
    const bool ok = c["pass"].get<bool>();
    h << "<tr><td>" << htmlEscape(c["model"]) << "</td><td>" << htmlEscape(c["voxel_size_mm"])
      << " mm</td><td>" << htmlEscape(c["method"]) << "</td><td>" << htmlEscape(c["mode"])
      << "</td><td class=\"" << (ok ? "pass\">pass" : "fail\">FAIL") << "</td><td>"
      << cell(c["border_edges"]) << "</td><td>" << cell(c["non_manifold"]) << "</td><td>"
      << cell(c["self_intersections"]) << "</td><td>" << cell(c["crack_percent"]) << "</td><td>"
      << cell(c["hausdorff_mm"]) << "</td><td>" << cell(c["collision_misses"]) << "</td><td>"
      << cell(c["collision_missed_samples"]) << " / " << cell(c["collision_rays"]) << "</td><td>"
      << cell(c["max_force_n"]) << "</td><td>" << cell(c["jitter_n"]) << "</td><td>";
    if (c.contains("after"))
      h << cell(c["after"]["border_edges"]) << " / " << cell(c["after"]["crack_percent"]);
    h << "</td></tr>\n";
  }
  h << "</table>\n";
  // The seed's Tables 1 and 2 (built-in humerus there: ViRCAST's own model) beside ours.
  h << "<h2>Mesh creation beside the seed's Tables 1 and "
       "2</h2><table><tr><th>model</th><th>voxel</th>"
    << "<th>voxels</th><th>triangles</th><th>vertices</th><th>mesh "
       "ms</th><th>extract</th><th>smooth</th>"
    << "<th>normals</th><th>other</th><th>seed's mesh ms</th></tr>\n";
  for (const json& c : report["cases"]) {
    if (c["method"] != "crackfree" || c["mode"] != "static") continue;
    const double vs = c["voxel_size_mm"].get<double>();
    const char* seed = std::abs(vs - 1.2) < 1e-9    ? "6"
                       : std::abs(vs - 0.9) < 1e-9  ? "14"
                       : std::abs(vs - 0.72) < 1e-9 ? "20"
                       : std::abs(vs - 0.54) < 1e-9 ? "34"
                                                    : "-";
    const json& t = c["mesh_time_ms"];
    h << "<tr><td>" << htmlEscape(c["model"]) << "</td><td>" << vs << " mm</td><td>"
      << cell(c["voxels"]) << "</td><td>" << cell(c["triangles"]) << "</td><td>"
      << cell(c["vertices"]) << "</td><td>" << cell(t["total"]) << "</td><td>" << cell(t["extract"])
      << "</td><td>" << cell(t["smooth"]) << "</td><td>" << cell(t["normals"]) << "</td><td>"
      << cell(t["other"]) << "</td><td>" << seed << "</td></tr>\n";
  }
  h << "</table>\n<h2>Failures</h2><ul>";
  for (const json& c : report["cases"]) {
    for (const json& f : c["failures"])
      h << "<li>" << htmlEscape(caseKey(c)) << ": " << htmlEscape(f) << "</li>";
  }
  h << "</ul>\n<h2>Crack views (seed 3.4: front faces white, back faces red)</h2>\n";
  for (const std::string& img : images)
    h << "<img src=\"" << htmlEscape(img) << "\" title=\"" << htmlEscape(img) << "\">";
  h << "\n<h2>Forces (as the seed's Figs. 6-8)</h2>\n";
  for (const json& p : report["plots"])
    h << "<img style=\"width:550px\" src=\"" << htmlEscape(p) << "\">";
  h << "\n<h2>Environment</h2><pre>" << htmlEscape(report["environment"].dump(2))
    << "</pre></body></html>\n";
  geometry::writeFileAtomically(path, h.str());
}

// The name each model's force logs and plots go by: its file stem as a file name (letters,
// digits, '.', '-', '_'), plus a short hash of its argument when two models would share it
// (default and big/default.obj), so no model's logs overwrite another's. The same --models
// give the same names in every shard of a run.
}  // namespace

void writeReport(json& j, const ValidateCommandOptions& options, const json& old,
                 const std::vector<std::string>& images) {
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
  std::cout << "verdict: " << j["verdict"].get<std::string>() << " (" << j["cases"].size()
            << " cases, " << j["regressions"].size() << " regressions, "
            << j["seconds"].get<double>() << " s); report: " << outDir << "/report.html\n";
  return j["verdict"] == "PASS" ? kExitOk : kExitCheckFailed;
}

}  // namespace osteon::cli
