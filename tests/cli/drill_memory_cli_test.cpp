// A drilling session this machine cannot hold is refused before the voxelizer starts, with the
// estimate against what there is (here a 2 GiB address-space limit stands for a small machine);
// it used to run for a minute and die of bad_alloc.
#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"
#include "support/files.h"

namespace osteon {
namespace {

using LimitedRun = test::ProcessRun;

LimitedRun underTwoGiB(const std::string& args, const std::string& errPath) {
  return test::runShell("ulimit -v 2097152; timeout 120 '" + std::string(OSTEON_CLI) + "' " + args,
                        "/dev/null", errPath);
}

TEST_F(CliTest, ADrillingSessionBeyondTheMachinesMemoryIsRefusedUpFront) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "sanitizers reserve terabytes of address space; an address-space limit stops "
                  "them at start";
#else
  const LimitedRun fine = underTwoGiB(
      "drill default --voxel-size 0.05 --path portal-5 --out-dir '" + path("o") + "'", path("err"));
  EXPECT_EQ(fine.exitCode, 2) << fine.err;
  EXPECT_LT(fine.seconds, 20.0) << "refused before voxelizing";
  EXPECT_EQ(
      fine.err.rfind(
          "osteon: error: default: a 52.7196 x 46.8551 x 149.449 mm mesh drilled at --voxel-size "
          "0.05 mm would need about ",
          0),
      0u)
      << fine.err;
  EXPECT_NE(
      fine.err.find(" GB of memory, more than this machine's 2.15 GB; use a larger --voxel-size"),
      std::string::npos)
      << fine.err;
  EXPECT_EQ(fine.err.find('\n'), fine.err.size() - 1) << fine.err;
  EXPECT_FALSE(std::filesystem::exists(path("o/forces.csv")));
  // The same machine holds a session at 0.6 mm (the estimate does not refuse what fits), and
  // the threaded runtime's front end is refused the same way.
  const LimitedRun coarse = underTwoGiB(
      "drill default --voxel-size 0.6 --levels 0 --path portal-5 --out-dir '" + path("c") + "'",
      path("err"));
  EXPECT_EQ(coarse.exitCode, 0) << coarse.err;
  const LimitedRun threaded = underTwoGiB(
      "drill default --voxel-size 0.05 --threaded --path portal-5 --out-dir '" + path("t") + "'",
      path("err"));
  EXPECT_EQ(threaded.exitCode, 2) << threaded.err;
  EXPECT_NE(threaded.err.find("would need about"), std::string::npos) << threaded.err;
#endif
}

}  // namespace
}  // namespace osteon
