// The `osteon` command as users and scripts meet it, run as a child process: exit code,
// stdout and stderr, each command bounded in time and memory so a runaway fails the test
// instead of the machine.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "support/files.h"
#include "support/process.h"
#include "support/shapes.h"

namespace osteon {

using CliRun = test::ProcessRun;

class CliTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("cli");
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

  CliRun osteon(const std::string& args) const {
    // 4 GiB of address space and 120 s: far above any command's need, far below a runaway's.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    // ASan and TSan reserve terabytes of address space for shadow memory, so `ulimit -v` would
    // stop every command at start-up; their allocators keep the same 4 GiB bound instead.
    const std::string limit =
        "export ASAN_OPTIONS=\"$ASAN_OPTIONS:max_allocation_size_mb=4096:hard_rss_limit_mb=4096\" "
        "TSAN_OPTIONS=\"$TSAN_OPTIONS:max_allocation_size_mb=4096:hard_rss_limit_mb=4096\"; ";
#else
    const std::string limit = "ulimit -v 4194304; ";
#endif
#ifdef OSTEON_SLOW_BUILD
    const std::string seconds =
        "1200";  // sanitizer builds run 2-15x slower (cmake/OsteonSanitizers.cmake)
#else
    const std::string seconds = "120";
#endif
    return test::runShell(limit + "timeout " + seconds + " '" + OSTEON_CLI + "' " + args,
                          path("stdout"), path("stderr"));
  }

  // Bad input: exit 2, nothing on stdout, one line on stderr that names `needle`.
  void expectBadInput(const std::string& args, const std::string& needle,
                      const std::string& reason) const {
    const CliRun run = osteon(args);
    EXPECT_EQ(run.exitCode, 2) << args << "\n" << run.err;
    EXPECT_TRUE(run.out.empty()) << args << "\n" << run.out;
    ASSERT_FALSE(run.err.empty()) << args;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "one line: " << run.err;
    EXPECT_NE(run.err.find(needle), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(reason), std::string::npos) << run.err;
  }
};

}  // namespace osteon
