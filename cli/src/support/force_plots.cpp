#include "support/force_plots.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"

namespace osteon::cli {

namespace {

// The gnuplot script drawing each figure into outputs[i], from each series' log as
// `logPath` gives it.
template <class LogPath>
std::string plotScript(const std::vector<ForceFigure>& figures,
                       const std::vector<std::string>& outputs, const LogPath& logPath) {
  std::ostringstream gp;
  gp << "set terminal pngcairo size 1100,600 font 'sans,12'\n"
     << "set datafile separator ','\nset grid\nset key top left box opaque\n"
     << "set xlabel 'time (s)'\nset ylabel 'force |F| (N)'\nset xrange [0:*]\nset yrange [0:3.5]\n";
  for (std::size_t k = 0; k < figures.size(); ++k) {
    const ForceFigure& f = figures[k];
    gp << "set output '" << outputs[k] << "'\nset title '" << f.title << "'\nplot ";
    for (std::size_t i = 0; i < f.series.size(); ++i) {
      gp << (i ? ", " : "") << "'" << logPath(f.series[i].csv)
         << "' every ::1 using 1:8 with lines lw " << f.series[i].lineWidth << " title '"
         << f.series[i].title << "'";
    }
    gp << "\n";
  }
  return gp.str();
}

}  // namespace

// gnuplot on `script`, its stderr into `log`, started directly: through a shell, the shell's
// own failures (its redirection fails under a low `ulimit -n`) looked like a missing gnuplot.
// Its log goes to logTemp, named `log` in messages. Throws InputError with the real reason: not
// installed, could not start (errno), or its exit status and the first line of its log.
void runGnuplot(const std::string& script, const std::string& logTemp, const std::string& log) {
  const int logFd = ::open(logTemp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (logFd < 0)
    throw InputError(log + ": cannot create gnuplot's log (" + std::strerror(errno) + ")");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, logFd, 2);
  std::string program = "gnuplot", argument = script;
  char* argv[] = {program.data(), argument.data(), nullptr};
  pid_t pid = -1;
  const int started = ::posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(logFd);
  if (started == ENOENT) {
    throw InputError(
        "gnuplot: not found on PATH, so the force plots cannot be drawn (scripts/setup installs "
        "gnuplot-nox)");
  }
  if (started != 0)
    throw InputError(std::string("gnuplot: could not start it (") + std::strerror(started) + ")");
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR)
      throw InputError(std::string("gnuplot: could not wait for it (") + std::strerror(errno) +
                       ")");
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  std::ifstream in(logTemp);
  std::string first;
  std::getline(in, first);
  std::ostringstream s;
  s << "gnuplot: could not draw the force plots (";
  if (WIFEXITED(status)) {
    s << "exit " << WEXITSTATUS(status);
  } else {
    s << "killed by signal " << WTERMSIG(status);
  }
  s << (first.empty() ? std::string() : ": " + first.substr(0, 200)) << "; see " << log << ")";
  throw InputError(s.str());
}

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
  geometry::writeFileAtomically(
      scriptPath, plotScript(figures, finals, [](const std::string& csv) { return csv; }));
  geometry::OutputFile runScript(scriptPath);
  {
    std::ofstream out(runScript.tempPath(), std::ios::binary | std::ios::trunc);
    out << plotScript(figures, temps, geometry::OutputDir::currentPath) << "unset output\n";
    out.close();
    if (!out) throw InputError(scriptPath + ": writing failed (disk full or not writable?)");
  }
  geometry::OutputFile log(scriptPath + ".log");
  try {
    runGnuplot(runScript.tempPath(), log.tempPath(), log.path());
  } catch (const InputError&) {
    std::error_code ec;  // in place now, run folder or not: the user reads why
    if (std::filesystem::exists(log.tempPath(), ec)) log.commitTo(log.path());
    throw;
  }
  log.commit();
  for (geometry::OutputFile& image : images) image.commit();
}

}  // namespace osteon::cli
