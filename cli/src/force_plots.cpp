#include "force_plots.h"

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_file.h"

#include <cstdlib>
#include <sstream>

namespace osteon::cli {

namespace {

// The gnuplot script drawing each figure into outputs[i].
std::string plotScript(const std::vector<ForceFigure>& figures, const std::vector<std::string>& outputs) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,600 font 'sans,12'\n"
     << "set datafile separator ','\nset grid\nset key top left box opaque\n"
     << "set xlabel 'time (s)'\nset ylabel 'force |F| (N)'\nset xrange [0:*]\nset yrange [0:3.5]\n";
  for (std::size_t k = 0; k < figures.size(); ++k) {
    const ForceFigure& f = figures[k];
    gp << "set output '" << outputs[k] << "'\nset title '" << f.title << "'\nplot ";
    for (std::size_t i = 0; i < f.series.size(); ++i) {
      gp << (i ? ", " : "") << "'" << f.series[i].csv << "' every ::1 using 1:8 with lines lw "
         << f.series[i].lineWidth << " title '" << f.series[i].title << "'";
    }
    gp << "\n";
  }
  return gp.str();
}

}  // namespace

void drawForcePlots(const std::vector<ForceFigure>& figures, const std::string& scriptPath) {
  // The saved script draws the final files; the one run draws temporary files, put in place
  // only once every figure is drawn.
  std::vector<std::string> finals, temps;
  std::vector<geometry::OutputFile> images;
  for (const ForceFigure& f : figures) {
    images.emplace_back(f.png);
    finals.push_back(f.png);
    temps.push_back(images.back().tempPath());
  }
  geometry::writeFileAtomically(scriptPath, plotScript(figures, finals));
  geometry::OutputFile runScript(scriptPath);
  geometry::writeFileAtomically(runScript.tempPath(), plotScript(figures, temps) + "unset output\n");
  const std::string log = scriptPath + ".log";
  const std::string command = "gnuplot '" + runScript.tempPath() + "' 2>'" + log + "'";
  if (std::system(command.c_str()) != 0) {
    throw InputError("gnuplot: could not draw the force plots (is gnuplot installed? scripts/setup "
                     "installs gnuplot-nox; see " + log + ")");
  }
  for (geometry::OutputFile& image : images) image.commit();
}

}  // namespace osteon::cli
