// Force plots in the manner of the seed's Figs. 6-8 (time on x, |F| in N on y, several runs on
// one set of axes), drawn by gnuplot from force logs (forces.csv: t in column 1, |F| in 8).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace osteon::cli {

struct ForceSeries {
  std::string csv;  // a force log
  std::string title;
  double lineWidth = 1.4;
};

struct ForceFigure {
  std::string png;  // output image
  std::string title;
  std::vector<ForceSeries> series;
};

// Any gnuplot figures: script(outputs, data) gives the script that draws the PNGs `outputs`
// from data files named through data(path). The script is saved at scriptPath (drawing pngs),
// run drawing temporaries, and the PNGs put in place together when every one is drawn; gnuplot's
// stderr goes to scriptPath + ".log". Throws InputError naming the log when gnuplot is missing or
// fails.
using DataPath = std::function<std::string(const std::string&)>;
using GnuplotScript =
    std::function<std::string(const std::vector<std::string>& outputs, const DataPath& data)>;
void drawGnuplotFigures(const std::string& scriptPath, const std::vector<std::string>& pngs,
                        const GnuplotScript& script);

// Writes the gnuplot script to scriptPath and runs it (stderr to scriptPath + ".log"). Throws
// InputError naming the log when gnuplot is missing or fails; the logs stay on disk.
void drawForcePlots(const std::vector<ForceFigure>& figures, const std::string& scriptPath);

}  // namespace osteon::cli
