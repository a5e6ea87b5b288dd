// Where a NRRD's data lies, through the command line: a `data file:` outside the header's
// folder needs --allow-outside-data, and data longer than the sizes say is refused from the
// file's size, before any of it is read.
#include <chrono>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <string>
#include <unistd.h>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;

// A 20^3 uint8 label map with a 10^3 cube of label 1 in the middle.
std::string cubeBytes() {
  std::string bytes(8000, '\0');
  for (int z = 5; z < 15; ++z) {
    for (int y = 5; y < 15; ++y) {
      for (int x = 5; x < 15; ++x) bytes[std::size_t((z * 20 + y) * 20 + x)] = 1;
    }
  }
  return bytes;
}

std::string header(const std::string& sizes, const std::string& encoding,
                   const std::string& extra) {
  return "NRRD0004\ntype: uint8\ndimension: 3\nsizes: " + sizes +
         "\nspacings: 1 1 1\nencoding: " + encoding + "\n" + extra;
}

// A file of `bytes` that takes no disk: ftruncate leaves it sparse.
void makeSparse(const std::string& path, off_t bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0) << path;
  ASSERT_EQ(::ftruncate(fd, bytes), 0) << path;
  ::close(fd);
}

class NrrdDataCli : public CliTest {
 protected:
  // `osteon ARGS` under an address-space limit of `limitMb`; returns the run and its seconds.
  CliRun boundedRun(const std::string& args, int limitMb, double& seconds) const {
    const auto start = std::chrono::steady_clock::now();
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    (void)limitMb;  // sanitizers reserve terabytes of address space at start-up
    const CliRun run = osteon(args);
#else
    const CliRun run = test::runShell(
        "ulimit -v " + std::to_string(limitMb * 1024) + "; timeout 60 '" + OSTEON_CLI + "' " + args,
        path("stdout"), path("stderr"));
#endif
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return run;
  }
};

TEST_F(NrrdDataCli, DataFileOutsideTheHeadersFolderNeedsTheFlag) {
  fs::create_directories(path("scans"));
  test::writeBytes(path("labels.raw"), cubeBytes());
  test::writeBytes(path("scans/h.nhdr"), header("20 20 20", "raw", "data file: ../labels.raw\n"));
  for (const char* command : {"mesh", "hierarchy"}) {
    SCOPED_TRACE(command);
    expectBadInput(std::string(command) + " '" + path("scans/h.nhdr") + "'", path("scans/h.nhdr"),
                   "is outside the header's folder");
    expectBadInput(std::string(command) + " '" + path("scans/h.nhdr") + "'", "labels.raw",
                   "give --allow-outside-data to read it");
  }
  const CliRun run = osteon("mesh '" + path("scans/h.nhdr") + "' --allow-outside-data --json");
  EXPECT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("\"label map\""), std::string::npos) << run.out;
  // A symlink in the folder that leads out of it is as far outside.
  fs::create_symlink("../labels.raw", path("scans/link.raw"));
  test::writeBytes(path("scans/h.nhdr"), header("20 20 20", "raw", "data file: link.raw\n"));
  expectBadInput("mesh '" + path("scans/h.nhdr") + "'", "link.raw",
                 "is outside the header's folder");
  EXPECT_EQ(osteon("mesh '" + path("scans/h.nhdr") + "' --allow-outside-data").exitCode, 0);
  // validate opens --models volumes through the same reader.
  const std::string validate =
      "validate --quick --models '" + path("scans/h.nhdr") + "' --out-dir '" + path("v") + "'";
  expectBadInput(validate, "link.raw", "is outside the header's folder");
  const CliRun validated = osteon(validate + " --allow-outside-data");
  EXPECT_EQ(validated.exitCode, 0) << validated.err;
}

// A 1-voxel header over a 3 GB file was read whole before its length was compared: seconds
// and gigabytes. The file's size now says it at once, within a few megabytes.
TEST_F(NrrdDataCli, HugeDataUnderATinyHeaderIsRefusedAtOnce) {
  const off_t huge = off_t(3) << 30;
  makeSparse(path("huge.raw"), huge);
  test::writeBytes(path("detached.nhdr"), header("1 1 1", "raw", "data file: huge.raw\n"));
  test::writeBytes(path("attached.nrrd"), header("1 1 1", "raw", "\n"));
  ASSERT_EQ(::truncate(path("attached.nrrd").c_str(), huge), 0);
  test::writeBytes(path("gzip.nhdr"), header("1 1 1", "gzip", "data file: huge.raw\n"));
  const struct {
    std::string file;
    std::string reason;
  } cases[] = {
      {"detached.nhdr", "huge.raw: 3221225472 bytes of data disagree with sizes, which need 1"},
      {"attached.nrrd", "bytes of data disagree with sizes, which need 1"},
      {"gzip.nhdr",
       "huge.raw: gzip data is corrupt"},  // zeros are no gzip stream: seen in the first bytes
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    double seconds = 0.0;
    const CliRun run =
        boundedRun("mesh '" + path(c.file) + "' --out '" + path("out.ply") + "'", 300, seconds);
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_NE(run.err.find(c.reason), std::string::npos) << run.err;
    EXPECT_LT(seconds, 5.0);
    EXPECT_FALSE(fs::exists(path("out.ply")));
  }
}

}  // namespace
}  // namespace osteon
