// One table of subcommands makes the help, the unknown-command message and the dispatch: every
// command the help lists is named by the message, in the same order, and runs (its --help).
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"

namespace osteon {
namespace {

// The names under "Subcommands:" in `osteon --help`.
std::vector<std::string> helpCommands(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream in(help.substr(help.find("Subcommands:")));
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line) && line.size() > 2 && line[0] == ' ') {
    std::istringstream words(line);
    std::string name;
    words >> name;
    names.push_back(name);
  }
  return names;
}

TEST_F(CliTest, TheHelpTheUnknownCommandMessageAndTheDispatchNameTheSameCommands) {
  const CliRun help = osteon("--help");
  ASSERT_EQ(help.exitCode, 0) << help.err;
  const std::vector<std::string> names = helpCommands(help.out);
  ASSERT_EQ(names.size(), 13u) << help.out;
  std::string expected;
  for (std::size_t i = 0; i < names.size(); ++i) {
    expected += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  const CliRun unknown = osteon("dril default");
  EXPECT_EQ(unknown.exitCode, 2);
  EXPECT_EQ(unknown.err, "osteon: error: dril: unknown command (expected " + expected +
                             "; see osteon --help)\n");
  for (const std::string& name : names) {
    const CliRun run = osteon(name + " --help");
    EXPECT_EQ(run.exitCode, 0) << name << ": " << run.err;
    EXPECT_NE(run.out.find(name), std::string::npos) << run.out;
  }
  // Each command runs its own work: `model` builds the bone, `devices list` lists.
  EXPECT_EQ(osteon("model --json").exitCode, 0);
  EXPECT_EQ(osteon("devices list --json").exitCode, 0);
  EXPECT_EQ(osteon("devices").exitCode, 2);   // a subcommand of devices is required
  EXPECT_EQ(osteon("exercise").exitCode, 2);  // and of exercise
}

}  // namespace
}  // namespace osteon
