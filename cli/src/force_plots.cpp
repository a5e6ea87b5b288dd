#include "force_plots.h"

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace osteon::cli {

namespace {

// The gnuplot script drawing each figure into outputs[i], from each series' log as
// `logPath` gives it.
template <class LogPath>
std::string plotScript(const std::vector<ForceFigure>& figures, const std::vector<std::string>& outputs,
                       const LogPath& logPath) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,600 font 'sans,12'\n"
     << "set datafile separator ','\nset grid\nset key top left box opaque\n"
     << "set xlabel 'time (s)'\nset ylabel 'force |F| (N)'\nset xrange [0:*]\nset yrange [0:3.5]\n";
  for (std::size_t k = 0; k < figures.size(); ++k) {
    const ForceFigure& f = figures[k];
    gp << "set output '" << outputs[k] << "'\nset title '" << f.title << "'\nplot ";
    for (std::size_t i = 0; i < f.series.size(); ++i) {
      gp << (i ? ", " : "") << "'" << logPath(f.series[i].csv) << "' every ::1 using 1:8 with lines lw "
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
  // The saved script reads the logs where they will be; this run reads them where they are
  // (held back until its run folder is complete, output_dir.h).
  geometry::writeFileAtomically(scriptPath, plotScript(figures, finals, [](const std::string& csv) { return csv; }));
  geometry::OutputFile runScript(scriptPath);
  {
    std::ofstream out(runScript.tempPath(), std::ios::binary | std::ios::trunc);
    out << plotScript(figures, temps, geometry::OutputDir::currentPath) << "unset output\n";
    out.close();
    if (!out) throw InputError(scriptPath + ": writing failed (disk full or not writable?)");
  }
  geometry::OutputFile log(scriptPath + ".log");
  const std::string command = "gnuplot '" + runScript.tempPath() + "' 2>'" + log.tempPath() + "'";
  if (std::system(command.c_str()) != 0) {
    log.commitTo(log.path());  // in place now, run folder or not: the user reads why
    throw InputError("gnuplot: could not draw the force plots (is gnuplot installed? scripts/setup "
                     "installs gnuplot-nox; see " + log.path() + ")");
  }
  log.commit();
  for (geometry::OutputFile& image : images) image.commit();
}

}  // namespace osteon::cli
