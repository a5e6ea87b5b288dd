// The golden table of bad inputs (tests/data/bad/README.md) through the command line: the
// hand-made cases of tests/data/bad/table.tsv and the generated ones of osteon_bad_inputs.
// Every case runs as its own process: exit code as listed, one line on stderr naming the
// file (and the reason where the table gives one), nothing on stdout, and at most 200 MB.
#include <chrono>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <signal.h>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/process.h"
#include "support/shapes.h"
#include "support/volume_files.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;

struct Case {
  std::string loader;
  std::string file;  // absolute
  int exitCode = 2;
  std::string reason;
};

std::vector<Case> readTable(const std::string& dir) {
  std::ifstream in(dir + "/table.tsv");
  EXPECT_TRUE(in) << dir << "/table.tsv";
  std::vector<Case> cases;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Case c;
    std::string file, code;
    std::getline(fields, c.loader, '\t');
    std::getline(fields, file, '\t');
    std::getline(fields, code, '\t');
    std::getline(fields, c.reason);
    c.file = dir + "/" + file;
    c.exitCode = std::stoi(code);
    cases.push_back(c);
  }
  return cases;
}

struct Outcome {
  int exitCode = -1;
  std::string out, err;
  double ms = 0.0;
  double peakMb = 0.0;
};

// osteon run directly (no shell between, so its own peak RSS is measured), killed after
// `limitS` as a hang.
Outcome runOsteon(const std::vector<std::string>& args, const std::string& scratch, double limitS,
                  rlim_t addressSpaceBytes = RLIM_INFINITY) {
  const std::string outPath = scratch + "/stdout", errPath = scratch + "/stderr";
  const auto start = std::chrono::steady_clock::now();
  const int o = open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int e = open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const pid_t pid = test::spawnProgram(OSTEON_CLI, args, o, e, addressSpaceBytes);
  close(o);
  close(e);
  Outcome r;
  int status = 0;
  rusage usage{};
  while (wait4(pid, &status, WNOHANG, &usage) == 0) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > limitS) {
      kill(pid, SIGKILL);
      wait4(pid, &status, 0, &usage);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  r.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  r.exitCode = test::exitCodeOf(status);
  r.peakMb = double(usage.ru_maxrss) / 1024.0;
  r.out = test::readBytes(outPath);
  r.err = test::readBytes(errPath);
  return r;
}

class BadInputTableTest : public CliTest {
 protected:
  void SetUp() override {
    cube_ = path("cube.stl");
    fs::create_directories(path("out"));
    geometry::writeMesh(test::makeBox({0, 0, 0}, {20, 20, 20}), cube_);
  }

  // The command that reads a `loader`'s file, as a user would run it.
  std::vector<std::string> commandFor(const Case& c) const {
    if (c.loader == "nrrd" || c.loader == "nifti" || c.loader == "dicom" || c.loader == "metaimage")
      return {"mesh", c.file, "--out", path("out/volume.ply")};
    if (c.loader == "path") {
      return {"drill", cube_,    "--voxel-size", "1",         "--levels",
              "0",     "--path", c.file,         "--out-dir", path("out/drill")};
    }
    if (c.loader == "recording") {
      return {"replay",   c.file, cube_,       "--voxel-size",    "1",
              "--levels", "0",    "--out-dir", path("out/replay")};
    }
    return {"info", c.file};
  }

  // Runs every case; returns how many ran.
  int runAll(const std::vector<Case>& cases) {
#ifdef OSTEON_SLOW_BUILD
    const double limitS = 600.0;
#else
    const double limitS = 60.0;
#endif
    int ran = 0;
    for (const Case& c : cases) {
      SCOPED_TRACE(c.loader + " " + c.file);
      const Outcome r = runOsteon(commandFor(c), dir_, limitS);
      ++ran;
      slowestMs_ = std::max(slowestMs_, r.ms);
      largestMb_ = std::max(largestMb_, r.peakMb);
      EXPECT_EQ(r.exitCode, c.exitCode) << r.err;
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
      EXPECT_LE(r.peakMb, 200.0);  // sanitizers' shadow memory is theirs, not osteon's
#endif
      if (c.exitCode != 2) continue;
      EXPECT_TRUE(r.out.empty()) << r.out;
      EXPECT_FALSE(r.err.empty());
      EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
      EXPECT_EQ(r.err.rfind("osteon: error: ", 0), 0u) << r.err;
      EXPECT_NE(r.err.find(fs::path(c.file).filename().string()), std::string::npos)
          << "names the file: " << r.err;
      if (!c.reason.empty()) {
        EXPECT_NE(r.err.find(c.reason), std::string::npos) << r.err;
      }
    }
    return ran;
  }

  void TearDown() override {
    std::printf("slowest case %.0f ms, largest peak RSS %.0f MB\n", slowestMs_, largestMb_);
    CliTest::TearDown();
  }

  std::string cube_;
  double slowestMs_ = 0.0;
  double largestMb_ = 0.0;
};

const std::string kData = std::string(OSTEON_SOURCE_DIR) + "/tests/data";

TEST_F(BadInputTableTest, EverySeedLoads) {
  // The truncations below are of these files, so each must be valid as it stands.
  std::vector<Case> seeds;
  for (const fs::directory_entry& e : fs::directory_iterator(kData + "/seeds")) {
    const std::string name = e.path().filename().string();
    const std::string ext = e.path().extension().string();
    // report.json seeds the report reader's fuzzer; osteon_report_reader_tests checks it.
    if (ext == ".raw" || ext == ".md" || ext == ".json") continue;
    std::string loader = ext.substr(1);
    if (ext == ".nhdr") loader = "nrrd";
    if (ext == ".nii" || ext == ".gz") loader = "nifti";
    if (ext == ".mha" || ext == ".mhd") loader = "metaimage";
    if (ext == ".dcm") loader = "dicom";
    if (ext == ".csv") loader = name.rfind("path", 0) == 0 ? "path" : "recording";
    seeds.push_back({loader, e.path().string(), 0, ""});
  }
  EXPECT_GE(runAll(seeds), 14);
}

TEST_F(BadInputTableTest, EveryHandMadeCaseIsRefusedWithItsReason) {
  EXPECT_GE(runAll(readTable(kData + "/bad")), 40);
}

TEST_F(BadInputTableTest, EveryGeneratedCaseIsRefused) {
  const std::string generated = path("generated");
  const std::string command = std::string("'") + OSTEON_BAD_INPUTS + "' generate '" + kData +
                              "/seeds' '" + generated + "' > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_GE(runAll(readTable(generated)), 200);
}

// A request past the machine's memory (here a 1.2 GB address-space limit stands for a small
// machine) is refused up front with its estimate, not killed halfway through.
TEST_F(BadInputTableTest, RequestsBeyondTheMachinesMemoryAreRefusedWithTheEstimate) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "sanitizers reserve terabytes of address space; an address-space limit stops "
                  "them at start";
#else
  const rlim_t limit = rlim_t(1200) << 20;
  const Outcome grid =
      runOsteon({"voxelize", "default", "--voxel-size", "0.05"}, dir_, 60.0, limit);
  EXPECT_EQ(grid.exitCode, 2) << grid.err;
  EXPECT_NE(grid.err.find("--voxel-size 0.05 mm would need about"), std::string::npos) << grid.err;
  EXPECT_NE(grid.err.find("of memory, more than this machine's 1.26 GB"), std::string::npos)
      << grid.err;
  EXPECT_LT(grid.peakMb, 100.0) << "refused before the grid is allocated";

  // A whole volume (its gzip data holds every voxel) that this machine cannot hold.
  test::writeBytes(path("big.nrrd"),
                   "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 1000 1000 200\nspacings: 1 1 1\n"
                   "encoding: gzip\n\n" +
                       test::gzipBytes(std::string(200'000'000, '\0')));
  const Outcome volume =
      runOsteon({"mesh", path("big.nrrd"), "--out", path("big.ply")}, dir_, 60.0, limit);
  EXPECT_EQ(volume.exitCode, 2) << volume.err;
  EXPECT_NE(
      volume.err.find("big.nrrd: a 1000 x 1000 x 200 volume would need about 1.48 GB of memory"),
      std::string::npos)
      << volume.err;
  // What helps a volume is fewer voxels, not the --voxel-size a mesh takes.
  EXPECT_NE(volume.err.find("crop or downsample it"), std::string::npos) << volume.err;
  EXPECT_EQ(volume.err.find("--voxel-size"), std::string::npos) << volume.err;
  EXPECT_LT(volume.peakMb, 100.0) << "refused before the volume is inflated";
#endif
}

}  // namespace
}  // namespace osteon
