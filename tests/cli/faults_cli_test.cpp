// Faults in a drilling run as a user meets them: a disk that fills while forces.csv is
// written, a visual surface update that throws. One line on stderr naming what failed, a
// non-zero exit, and the force log's rows from before the fault whole in forces.csv.partial.
#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <sys/resource.h>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"
#include "support/files.h"

namespace osteon {
namespace {

constexpr char kHeader[] = "t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level\n";

class FaultCliTest : public CliTest {
 protected:
  // The command with files limited to `bytes`, as a disk with that much room left: writes past
  // it fail with EFBIG (SIGXFSZ ignored, as the shell passes it on), the way ENOSPC fails them.
  CliRun osteonOnSmallDisk(const std::string& args, rlim_t bytes) const {
    rlimit old{};
    getrlimit(RLIMIT_FSIZE, &old);
    rlimit small = old;
    small.rlim_cur = bytes;
    void (*oldHandler)(int) = std::signal(SIGXFSZ, SIG_IGN);
    setrlimit(RLIMIT_FSIZE, &small);
    const CliRun run = osteon(args);
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, oldHandler);
    return run;
  }

  CliRun osteonWithFault(const std::string& args, const char* fault) const {
    setenv("OSTEON_INJECT_FAULT", fault, 1);
    const CliRun run = osteon(args);
    unsetenv("OSTEON_INJECT_FAULT");
    return run;
  }

  // One line on stderr, nothing on stdout.
  static void expectOneLineError(const CliRun& run, int exitCode) {
    EXPECT_EQ(run.exitCode, exitCode) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
    ASSERT_FALSE(run.err.empty());
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "one line: " << run.err;
  }

  // A partial log: the header, then whole rows of 11 fields. Returns the rows.
  static std::size_t expectWholeRows(const std::string& log) {
    EXPECT_EQ(log.rfind(kHeader, 0), 0u);
    EXPECT_EQ(log.back(), '\n');
    std::istringstream in(log);
    std::string line;
    std::size_t rows = 0;
    std::getline(in, line);
    while (std::getline(in, line)) {
      EXPECT_EQ(std::count(line.begin(), line.end(), ','), 10) << "row " << rows << ": " << line;
      ++rows;
    }
    return rows;
  }
};

TEST_F(FaultCliTest, ADiskThatFillsKeepsTheWholeRowsLoggedBeforeAndSaysSoInOneLine) {
  const std::string args = "drill default --voxel-size 1.2 --levels 0 --path portal-5 --out-dir ";
  ASSERT_EQ(osteon(args + "'" + path("full") + "'").exitCode, 0);
  const std::string full = test::readBytes(path("full/forces.csv"));

  const CliRun run = osteonOnSmallDisk(args + "'" + path("small") + "'", 200000);
  expectOneLineError(run, 2);
  const std::string forces = path("small/forces.csv");
  EXPECT_EQ(
      run.err.rfind(
          "osteon: error: " + forces + ": cannot write the force log (File too large); the ", 0),
      0u)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(forces));
  EXPECT_FALSE(std::filesystem::exists(path("small/summary.json")));
  const std::string kept = test::readBytes(forces + ".partial");
  const std::size_t rows = expectWholeRows(kept);
  std::printf("[ disk     ] drill: %zu of %lld rows kept in %zu bytes; %s", rows,
              static_cast<long long>(std::count(full.begin(), full.end(), '\n') - 1), kept.size(),
              run.err.c_str());
  EXPECT_GT(rows, 1000u);
  EXPECT_LE(kept.size(), 200000u);
  EXPECT_EQ(full.compare(0, kept.size(), kept), 0)
      << "the kept rows are the complete log's first rows";
  EXPECT_NE(run.err.find("the " + std::to_string(rows) + " rows written before it are kept in " +
                         forces + ".partial"),
            std::string::npos)
      << run.err;

  // The same on the threaded runtime: the writer is on the logging thread, the loops go on.
  const CliRun threaded = osteonOnSmallDisk(args + "'" + path("threaded") + "' --threaded", 200000);
  expectOneLineError(threaded, 2);
  EXPECT_NE(threaded.err.find(path("threaded/forces.csv") +
                              ": cannot write the force log (File too large)"),
            std::string::npos)
      << threaded.err;
  EXPECT_GT(expectWholeRows(test::readBytes(path("threaded/forces.csv.partial"))), 1000u);

  // Room again: the run succeeds and the partial log of the failed one goes.
  ASSERT_EQ(osteon(args + "'" + path("small") + "'").exitCode, 0);
  EXPECT_EQ(test::readBytes(forces), full);
  EXPECT_FALSE(std::filesystem::exists(forces + ".partial"));
}

TEST_F(FaultCliTest, ASurfaceUpdateThatThrowsEndsTheThreadedDrillWithOneLine) {
  const std::string args =
      "drill default --voxel-size 1.2 --levels 0 --path portal-5 --threaded --out-dir '" +
      path("t") + "'";
  const CliRun run = osteonWithFault(args, "surface-update");
  expectOneLineError(run, 3);  // not the input's fault
  std::printf("[ fault    ] drill --threaded: %s", run.err.c_str());
  EXPECT_EQ(run.err.rfind(
                "osteon: internal error: the visual surface update failed: injected fault "
                "(OSTEON_INJECT_FAULT=surface-update); the haptic and collision loops were stopped "
                "cleanly after ",
                0),
            0u)
      << run.err;
  EXPECT_FALSE(std::filesystem::exists(path("t/forces.csv")));
  const std::size_t rows = expectWholeRows(test::readBytes(path("t/forces.csv.partial")));
  EXPECT_GT(rows, 0u);
  EXPECT_LT(rows, 7001u);  // stopped at the first cut, not at the path's end
  const std::string note = "; the " + std::to_string(rows) +
                           " rows written before it are kept in " + path("t/forces.csv.partial") +
                           "\n";
  EXPECT_EQ(run.err.size() - run.err.rfind(note), note.size()) << run.err;

  const CliRun unknown = osteonWithFault(args, "disk");
  expectOneLineError(unknown, 2);
  EXPECT_NE(unknown.err.find("OSTEON_INJECT_FAULT=disk: unknown fault"), std::string::npos)
      << unknown.err;
}

}  // namespace
}  // namespace osteon
