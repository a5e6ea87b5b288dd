// `osteon`: the command-line front end. The table of subcommands (command_table.h) gives the
// registration, the help, the unknown-command message and the dispatch; this file parses and
// turns what a command throws into one line on stderr and an exit code.
#include <csignal>
#include <exception>
#include <iostream>
#include <new>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "command_table.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/simulation/bone_source.h"

namespace {

using osteon::kExitBadInput;
using osteon::kExitInternal;
using osteon::kExitOk;

// CLI11 reports problems in paragraphs; we promise one line.
using osteon::oneLine;

// "info, voxelize, ... or model": the table's names, for the unknown-command message.
std::string commandList() {
  const auto& table = osteon::cli::subcommands();
  std::string list;
  for (std::size_t i = 0; i < table.size(); ++i) {
    list += (i == 0 ? "" : i + 1 == table.size() ? " or " : ", ") + std::string(table[i].name);
  }
  return list;
}

// Runs a parsed command; what it throws becomes one line on stderr and the exit code.
int runReporting(const std::function<int()>& run) {
  try {
    return run();
  } catch (const osteon::Interrupted& e) {
    // The run's folder keeps its previous outputs (output_dir.h): nothing of this run is in it.
    std::cerr << "osteon: " << e.what()
              << ": the run stopped; its output folder keeps what it held before\n";
    return e.exitCode();
  } catch (const osteon::InputError& e) {
    std::cerr << "osteon: error: " << oneLine(osteon::simulation::commandLineMessage(e)) << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "osteon: error: out of memory: the input needs more memory than this machine "
                 "has (a larger --voxel-size needs less)\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "osteon: internal error: " << oneLine(e.what()) << "\n";
    return kExitInternal;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // A write past `ulimit -f` then fails with EFBIG, told as one line naming the file, instead of
  // killing the process mid-file.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"osteon: crack-free multi-resolution bone drilling, from mesh to voxels to proof"};
  app.set_version_flag("--version", std::string("osteon ") + OSTEON_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands;
  for (const osteon::cli::Subcommand& s : osteon::cli::subcommands()) {
    CLI::App* command = app.add_subcommand(s.name, s.help);
    commands.emplace_back(command, s.attach(*command));
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return kExitOk;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return kExitOk;
  } catch (const CLI::CallForVersion&) {
    std::cout << "osteon " << OSTEON_VERSION << "\n";
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    // Name an unknown command rather than CLI11's "a subcommand is required".
    bool known = false;
    for (const auto& command : commands)
      known = known || (argc > 1 && command.first->get_name() == argv[1]);
    if (argc > 1 && argv[1][0] != '-' && !known) {
      std::cerr << "osteon: error: " << argv[1] << ": unknown command (expected " << commandList()
                << "; see osteon --help)\n";
      return kExitBadInput;
    }
    std::cerr << "osteon: error: " << oneLine(e.what()) << " (see osteon --help)\n";
    return kExitBadInput;
  }
  for (const auto& [command, run] : commands) {
    if (*command) return runReporting(run);
  }
  return kExitBadInput;
}
