// `osteon experiment heat`: Augustin et al. 2008 rerun (heat_experiment.h). The peak
// temperatures beside the paper's, as heat.md and heat.json, and heat.png drawn by gnuplot;
// exit 1 when the model breaks one of the paper's findings.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands/experiment.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/heat_experiment.h"
#include "support/force_plots.h"
#include "support/output.h"

namespace osteon::cli {

namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

// The speed x diameter grid the paper's range covers, apart from the feed series.
bool inGrid(const sim::HeatRun& r) {
  return !r.setting.feedSeries;
}

const char* publishedWithout(const sim::HeatRun& r) {
  if (!inGrid(r)) return "falls as feed rises";
  return sim::HeatPublished::aboveCritical(r.setting) ? "> 47 (of 31.4-55.5)"
                                                      : "< 47 (of 31.4-55.5)";
}

struct Check {
  std::string what;
  bool pass;
};

struct HeatReport {
  std::string outDir;
  std::vector<sim::HeatRun> runs;
  sim::HeatExperimentOptions options;
  std::vector<Check> checks;
  double minC = 0.0, maxC = 0.0;  // over the grid, without irrigation
};

// The paper's findings, each as the model's runs keep it or not.
std::vector<Check> checksOf(HeatReport& r) {
  const sim::HeatPublished p;
  r.minC = 1e9;
  r.maxC = -1e9;
  bool critical = true, irrigated = true, feedFalls = true, hottest = true;
  const sim::HeatRun* top = nullptr;
  double lastFeedC = 1e9;
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    const sim::HeatRun& run = r.runs[i];
    irrigated = irrigated && run.peakC[1] < p.criticalC;
    if (inGrid(run)) {
      r.minC = std::min(r.minC, run.peakC[0]);
      r.maxC = std::max(r.maxC, run.peakC[0]);
      critical = critical && (run.peakC[0] > p.criticalC) == p.aboveCritical(run.setting);
      if (!top || run.peakC[0] > top->peakC[0]) top = &run;
    } else {
      feedFalls = feedFalls && run.peakC[0] < lastFeedC;
      lastFeedC = run.peakC[0];
    }
  }
  hottest = top && top->setting.diameterMm == 4.5 && top->setting.rpm == 1820.0;
  char range[160];
  std::snprintf(range, sizeof range,
                "without irrigation, %.1f-%.1f °C within 2 °C of the published 31.4-55.5 °C",
                r.minC, r.maxC);
  return {{range, std::abs(r.minC - p.minC) <= 2.0 && std::abs(r.maxC - p.maxC) <= 2.0},
          {"above 47 °C only with the 4.5 mm drill at 1140 and 1820 rpm", critical},
          {"the 4.5 mm drill at 1820 rpm the hottest", hottest},
          {"with irrigation, every setting below 47 °C", irrigated},
          {"the higher the feed, the lower the temperature (4.5 mm, 1820 rpm)", feedFalls}};
}

json toJson(const HeatReport& r) {
  json rows = json::array();
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    const sim::HeatRun& h = r.runs[i];
    rows.push_back({{"diameter_mm", h.setting.diameterMm},
                    {"rpm", h.setting.rpm},
                    {"feed_mm_per_min", h.setting.feedMmPerMin},
                    {"feed_series", h.setting.feedSeries},
                    {"thrust_n", h.thrustN},
                    {"drill_s", h.drillS},
                    {"removed_mm3", h.removedMm3},
                    {"heat_into_bone_j", h.depositedJ},
                    {"peak_c", h.peakC[0]},
                    {"peak_irrigated_c", h.peakC[1]},
                    {"published", publishedWithout(h)},
                    {"published_irrigated", "< 47"},
                    {"grid_peak_c", h.gridPeakC[0]},
                    {"grid_peak_irrigated_c", h.gridPeakC[1]},
                    {"damaged_mm3", h.damagedMm3[0]},
                    {"damaged_irrigated_mm3", h.damagedMm3[1]},
                    {"damaged_bone_mm3", h.damagedBoneMm3[0]},
                    {"damaged_bone_irrigated_mm3", h.damagedBoneMm3[1]}});
  }
  json checks = json::array();
  for (const Check& c : r.checks) checks.push_back({{"finding", c.what}, {"pass", c.pass}});
  const sim::CuttingHeatModel& c = r.options.thermal.cutting;
  return {{"experiment", "heat"},
          {"source", "Augustin et al. 2008, Arch Orthop Trauma Surg 128:71-77"},
          {"model",
           {{"specific_energy_j_per_mm3", c.specificEnergyJPerMm3},
            {"friction_coefficient", c.frictionCoefficient},
            {"heat_fraction", c.heatFraction},
            {"irrigation_w_per_m2k", r.options.thermal.irrigationWPerM2K},
            {"conductivity_w_per_mk", r.options.thermal.bone.conductivityWPerMK}}},
          {"residuals_c", {{"min", r.minC - 31.4}, {"max", r.maxC - 55.5}}},
          {"runs", rows},
          {"checks", checks},
          {"plot", "heat.png"}};
}

std::string table(const HeatReport& r) {
  std::ostringstream md;
  md << "| drill | rpm | feed (mm/min) | thrust (N) | peak (°C) | published | irrigated peak (°C) "
        "| published | damaged bone (mm3) | irrigated "
        "|\n|---:|---:|---:|---:|---:|---|---:|---|---:|---:|\n";
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    const sim::HeatRun& h = r.runs[i];
    char line[320];
    std::snprintf(line, sizeof line,
                  "| %.1f mm | %.0f | %.0f | %.0f | %.1f | %s | %.1f | < 47 | %.1f | %.1f |\n",
                  h.setting.diameterMm, h.setting.rpm, h.setting.feedMmPerMin, h.thrustN,
                  h.peakC[0], publishedWithout(h), h.peakC[1], h.damagedBoneMm3[0],
                  h.damagedBoneMm3[1]);
    md << line;
  }
  md << "\n";
  for (const Check& c : r.checks) md << "- " << (c.pass ? "ok" : "FAIL") << ": " << c.what << "\n";
  return md.str();
}

void printText(const HeatReport& r) {
  std::cout << table(r) << "plot: " << r.outDir << "/heat.png\n";
}

// heat.dat (one block per drill, then the feed series) and the script drawing heat.png.
std::string plotData(const HeatReport& r) {
  std::ostringstream d;
  double last = -1.0;
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    const sim::HeatRun& h = r.runs[i];
    const double key = inGrid(h) ? h.setting.diameterMm : 0.0;
    if (last >= 0.0 && key != last) d << "\n\n";
    last = key;
    d << (inGrid(h) ? h.setting.rpm : h.setting.feedMmPerMin) << " " << h.peakC[0] << " "
      << h.peakC[1] << "\n";
  }
  return d.str();
}

std::string plotScript(const std::string& dat, const std::string& png) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1200,560 font 'sans,11'\nset output '" << png << "'\n"
     << "set multiplot layout 1,2 title 'Peak bone temperature, model beside Augustin et al. "
        "2008 (thermocouple 0.5 mm from the 4.5 mm hole)'\n"
     << "set grid\nset key top left box opaque\nset ylabel 'peak temperature (°C)'\n"
     << "set yrange [20:70]\nset style fill transparent solid 0.12 noborder\n"
     << "set xlabel 'drill speed (rpm), feed 84 mm/min'\nset xrange [0:2000]\n"
     << "plot 31.4 with lines dt 3 lc rgb 'gray40' title 'published range 31.4-55.5', 55.5 with "
        "lines dt 3 lc rgb 'gray40' notitle, 47 with lines lw 2 lc rgb 'red' title '47 °C', \\\n";
  const char* colors[] = {"#1f77b4", "#2ca02c", "#d62728"};
  const char* names[] = {"2.5 mm", "3.2 mm", "4.5 mm"};
  for (int b = 0; b < 3; ++b) {
    gp << "  '" << dat << "' index " << b << " using 1:2 with linespoints lw 2 pt 7 lc rgb '"
       << colors[b] << "' title '" << names[b] << "', '" << dat << "' index " << b
       << " using 1:3 with linespoints lw 2 dt 2 pt 6 lc rgb '" << colors[b] << "' title '"
       << names[b] << " irrigated'" << (b < 2 ? ", \\\n" : "\n");
  }
  gp << "set xlabel 'feed (mm/min), 4.5 mm drill at 1820 rpm'\nset xrange [0:220]\n"
     << "plot 47 with lines lw 2 lc rgb 'red' title '47 °C', '" << dat
     << "' index 3 using 1:2 with linespoints lw 2 pt 7 lc rgb '#d62728' title 'no irrigation', "
     << "'" << dat << "' index 3 using 1:3 with linespoints lw 2 dt 2 pt 6 lc rgb '#d62728' "
     << "title 'irrigated'\nunset multiplot\n";
  return gp.str();
}

void drawPlot(const std::string& dir) {
  drawGnuplotFigures(dir + "/heat.gp", {dir + "/heat.png"},
                     [&dir](const std::vector<std::string>& outputs, const DataPath& data) {
                       return plotScript(data(dir + "/heat.dat"), outputs[0]);
                     });
}

}  // namespace

int runHeatExperiment(const ExperimentCommandOptions& options) {
  if (options.bone.input != "default")
    throw InputError("--mesh " + options.bone.input +
                     ": experiment heat drills a cortical block, not a mesh");
  HeatReport report;
  report.outDir = options.outDir;
  geometry::OutputDir outDir(options.outDir,
                             {"heat.json", "heat.md", "heat.dat", "heat.gp", "heat.png"});
  report.runs =
      sim::runHeatExperiment(sim::augustinSettings(), report.options, [&](const sim::HeatRun& r) {
        throwIfInterrupted();
        if (!options.json) {
          std::cerr << "  " << r.setting.diameterMm << " mm, " << r.setting.rpm << " rpm, "
                    << r.setting.feedMmPerMin << " mm/min: " << r.peakC[0] << " °C\n";
        }
      });
  report.checks = checksOf(report);
  geometry::writeFileAtomically(options.outDir + "/heat.json", toJson(report).dump(2) + "\n");
  geometry::writeFileAtomically(options.outDir + "/heat.md", table(report));
  geometry::writeFileAtomically(options.outDir + "/heat.dat", plotData(report));
  try {
    drawPlot(options.outDir);
  } catch (const InputError&) {
    outDir.commit();  // the table is kept when gnuplot is missing
    throw;
  }
  outDir.commit();
  printReport(report, options.json);
  for (const Check& c : report.checks)
    if (!c.pass) return kExitCheckFailed;
  return kExitOk;
}

}  // namespace osteon::cli
