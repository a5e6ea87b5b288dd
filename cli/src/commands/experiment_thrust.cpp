// `osteon experiment thrust`: the calibrated cutting resistance against the published drilling
// thrust (docs/feel.md). Blocks of cortical and cancellous bone drilled at the published
// settings under the calibrated model and the seed's; the steady thrust beside the literature,
// as thrust.md, thrust.json, the force logs and two gnuplot figures.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands/experiment.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/thrust_experiment.h"
#include "support/force_plots.h"
#include "support/output.h"

namespace osteon::cli {

namespace sim = osteon::simulation;
using nlohmann::json;

namespace {

struct ThrustRow {
  sim::ThrustResult calibrated, seed;
};

std::string number(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string table(const std::vector<ThrustRow>& rows) {
  std::ostringstream md;
  md << "# Drilling thrust: osteon's calibrated model against the published figures\n\n"
     << "Steady thrust while the tip feeds at the commanded rate (the hand's push along the "
        "tool, N), on the device and in real newtons (device / "
     << number(sim::kDeviceNPerRealN, 5) << "). The seed's model ignores rpm and feed.\n\n"
     << "| material | drill | rpm | feed (mm/s) | published (N) | law (N) | simulated (N) | "
        "device (N) | fed (mm/s) | seed model, device (N) |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ThrustRow& r : rows) {
    const sim::ThrustResult& c = r.calibrated;
    md << "| " << c.c.material << " | " << c.c.diameterMm << " mm | " << c.c.rpm << " | "
       << c.c.feedMmPerS << " | "
       << (c.c.publishedN > 0 ? number(c.c.publishedN, 2) + " (" + c.c.source + ")" : "-") << " | "
       << number(c.lawN, 2) << " | " << number(c.realN, 2) << " | " << number(c.deviceN, 3) << " | "
       << number(c.feedMmPerS, 2) << " | " << number(r.seed.deviceN, 3) << " |\n";
  }
  return md.str();
}

json toJson(const std::vector<ThrustRow>& rows) {
  json cases = json::array();
  for (const ThrustRow& r : rows) {
    const sim::ThrustResult& c = r.calibrated;
    cases.push_back({{"name", c.c.name()},
                     {"material", c.c.material},
                     {"diameter_mm", c.c.diameterMm},
                     {"rpm", c.c.rpm},
                     {"feed_mm_per_s", c.c.feedMmPerS},
                     {"published_n", c.c.publishedN > 0 ? json(c.c.publishedN) : json(nullptr)},
                     {"source", c.c.source},
                     {"law_n", c.lawN},
                     {"simulated_n", c.realN},
                     {"device_n", c.deviceN},
                     {"fed_mm_per_s", c.feedMmPerS},
                     {"seed_device_n", r.seed.deviceN}});
  }
  const sim::ThrustModel m;
  return {{"model",
           {{"k_n_per_g_cm3", m.kNPerGcm3},
            {"rho0_g_cm3", m.rho0Gcm3},
            {"alpha", m.alpha},
            {"device_n_per_real_n", sim::kDeviceNPerRealN}}},
          {"cases", cases}};
}

// thrust.png: published, law and simulated thrust per case (log scale); thrust_time.png: the
// hand's push over time in the published cases.
std::string script(const std::vector<ThrustRow>& rows, const std::string& dir,
                   const std::vector<std::string>& outputs, const DataPath& data) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,600 font 'sans,12'\nset datafile separator ','\n"
     << "set grid\nset key top right box opaque\n"
     << "set output '" << outputs[0] << "'\n"
     << "set title 'Drilling thrust: published, the fitted law, and osteon drilling a block'\n"
     << "set ylabel 'thrust (N, real)'\nset logscale y\nset yrange [0.5:400]\n"
     << "set xrange [-0.6:" << double(rows.size()) - 0.4 << "]\nset xtics rotate by -25 font ',9'\n"
     << "set style fill solid 0.5\nset boxwidth 0.25\n"
     << "plot '" << data(dir + "/thrust.csv") << "' every ::1 using ($0-0.15):5:xtic(1) with boxes "
     << "title 'simulated (calibrated)', '' every ::1 using ($0+0.15):4 with boxes title "
        "'thrust law', '' every ::1 using 0:3 with points pt 7 ps 1.8 title 'published'\n"
     << "unset logscale y\nunset xtics\nset xtics\nset xrange [0:*]\nset yrange [0:3.5]\n"
     << "set output '" << outputs[1] << "'\n"
     << "set title 'The hand pushing the drill into bone: calibrated model (device N)'\n"
     << "set key bottom right\nset xlabel 'time (s)'\nset ylabel 'push along the tool (N, "
        "device)'\nplot ";
  bool first = true;
  for (const ThrustRow& r : rows) {
    if (!(r.calibrated.c.publishedN > 0)) continue;
    gp << (first ? "" : ", ") << "'" << data(dir + "/runs/" + r.calibrated.c.name() + "/forces.csv")
       << "' every ::1 using 1:10 with lines lw 1.4 title '" << r.calibrated.c.material << " "
       << r.calibrated.c.rpm << " rpm'";
    first = false;
  }
  gp << "\n";
  return gp.str();
}

}  // namespace

int runThrustExperiment(const ExperimentCommandOptions& options, const std::string& outDirPath) {
  if (options.bone.input != "default")
    throw InputError("--mesh: experiment thrust drills blocks of its own, not a mesh");
  const std::vector<std::string> owned = {"runs",      "thrust.md",  "thrust.json",    "thrust.csv",
                                          "thrust.gp", "thrust.png", "thrust_time.png"};
  geometry::OutputDir outDir(outDirPath, owned);
  std::vector<ThrustRow> rows;
  for (const sim::ThrustCase& c : sim::thrustExperimentCases()) {
    ThrustRow r{sim::runThrustCase(c, sim::ForceModelKind::Calibrated),
                sim::runThrustCase(c, sim::ForceModelKind::Seed)};
    throwIfInterrupted();
    const std::string dir = outDirPath + "/runs/" + c.name();
    std::filesystem::create_directories(dir);
    sim::writeForceLog(r.calibrated.log, dir + "/forces.csv", true, true);
    if (!options.json) {
      std::cerr << "  " << c.name() << ": " << number(r.calibrated.realN, 1) << " N (device "
                << number(r.calibrated.deviceN, 3) << " N)\n";
    }
    r.calibrated.log.clear();
    r.seed.log.clear();
    rows.push_back(std::move(r));
  }
  std::ostringstream csv;
  csv << "case,published_n,published_or_nan,law_n,simulated_n\n";
  for (const ThrustRow& r : rows) {
    const sim::ThrustResult& c = r.calibrated;
    csv << c.c.material << " " << c.c.rpm << " rpm " << c.c.feedMmPerS << " mm/s," << c.c.publishedN
        << "," << (c.c.publishedN > 0 ? number(c.c.publishedN, 3) : "NaN") << "," << c.lawN << ","
        << c.realN << "\n";
  }
  geometry::writeFileAtomically(outDirPath + "/thrust.csv", csv.str());
  geometry::writeFileAtomically(outDirPath + "/thrust.json", toJson(rows).dump(2) + "\n");
  const std::string md = table(rows);
  geometry::writeFileAtomically(outDirPath + "/thrust.md", md);
  try {
    drawGnuplotFigures(outDirPath + "/thrust.gp",
                       {outDirPath + "/thrust.png", outDirPath + "/thrust_time.png"},
                       [&](const std::vector<std::string>& outputs, const DataPath& data) {
                         return script(rows, outDirPath, outputs, data);
                       });
  } catch (const InputError&) {
    outDir.commit();
    throw;
  }
  outDir.commit();
  if (options.json) {
    std::cout << toJson(rows).dump(2) << "\n";
  } else {
    std::cout << md;
  }
  return kExitOk;
}

}  // namespace osteon::cli
