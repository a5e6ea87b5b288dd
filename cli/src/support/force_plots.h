// Force plots in the manner of the seed's Figs. 6-8 (time on x, |F| in N on y, several runs on
// one set of axes), drawn by gnuplot from force logs (forces.csv: t in column 1, |F| in 8).
#pragma once

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

// Writes the gnuplot script to scriptPath and runs it (stderr to scriptPath + ".log"). Throws
// InputError naming the log when gnuplot is missing or fails; the logs stay on disk.
void drawForcePlots(const std::vector<ForceFigure>& figures, const std::string& scriptPath);

// gnuplot on the script file `script`, its stderr into logTemp (named `log` in messages). Throws
// InputError with the reason: not installed, could not start, or its exit status and log's
// first line.
void runGnuplot(const std::string& script, const std::string& logTemp, const std::string& log);

}  // namespace osteon::cli
