#include "force_plots.h"

#include "osteon/geometry/error.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace osteon::cli {

void drawForcePlots(const std::vector<ForceFigure>& figures, const std::string& scriptPath) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,600 font 'sans,12'\n"
     << "set datafile separator ','\nset grid\nset key top left box opaque\n"
     << "set xlabel 'time (s)'\nset ylabel 'force |F| (N)'\nset xrange [0:*]\nset yrange [0:3.5]\n";
  for (const ForceFigure& f : figures) {
    gp << "set output '" << f.png << "'\nset title '" << f.title << "'\nplot ";
    for (std::size_t i = 0; i < f.series.size(); ++i) {
      gp << (i ? ", " : "") << "'" << f.series[i].csv << "' every ::1 using 1:8 with lines lw "
         << f.series[i].lineWidth << " title '" << f.series[i].title << "'";
    }
    gp << "\n";
  }
  {
    std::ofstream out(scriptPath);
    out << gp.str();
    if (!out) throw InputError(scriptPath + ": cannot write the plot script");
  }
  const std::string log = scriptPath + ".log";
  const std::string command = "gnuplot '" + scriptPath + "' 2>'" + log + "'";
  if (std::system(command.c_str()) != 0) {
    throw InputError("gnuplot: could not draw the force plots (is gnuplot installed? scripts/setup "
                     "installs gnuplot-nox; see " + log + ")");
  }
}

}  // namespace osteon::cli
