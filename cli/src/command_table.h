// The subcommands of `osteon`, one row each: main.cpp generates from this table their CLI11
// registration, the help, the unknown-command message and the dispatch.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace osteon::cli {

struct Subcommand {
  const char* name;
  const char* help;
  // Adds the command's options to `command` (its CLI::App) and returns what runs the command
  // once the command line is parsed; returns the exit code.
  std::function<std::function<int()>(CLI::App& command)> attach;
};

// In the order `osteon --help` lists them.
const std::vector<Subcommand>& subcommands();

}  // namespace osteon::cli
