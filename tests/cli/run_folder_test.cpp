// A run's --out-dir holds one set: the previous run's files whole, or this run's, never a mix.
// Guards against a run stopped by SIGINT or SIGTERM (exit 130/143, the previous set untouched,
// no temporary left), a killed run's temporaries staying forever, two runs filling one folder
// at once, two models of the same file stem writing over each other's force logs, and
// `--record` destroying an existing recording before the new one is complete.
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <map>
#include <poll.h>
#include <set>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>

#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/process.h"

namespace osteon {
namespace {

namespace fs = std::filesystem;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

// Every file below `dir` (hidden ones too), relative, with its bytes.
std::map<std::string, std::string> filesIn(const std::string& dir) {
  std::map<std::string, std::string> files;
  if (!fs::exists(dir)) return files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file())
      files[fs::relative(e.path(), dir).string()] = test::readBytes(e.path().string());
  }
  return files;
}

// An osteon process of the test's own, so it can be signalled midway: its stdout and stderr
// are read as they come.
class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    int out[2], err[2];
    EXPECT_EQ(::pipe(out), 0);
    EXPECT_EQ(::pipe(err), 0);
    pid_ = test::spawnProgram(OSTEON_CLI, args, out[1], err[1]);
    ::close(out[1]);
    ::close(err[1]);
    fds_[0] = out[0];
    fds_[1] = err[0];
  }
  ~Child() {
    if (!reaped_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  pid_t pid() const { return pid_; }
  const std::string& out() const { return text_[0]; }
  const std::string& err() const { return text_[1]; }

  // Reads until stdout or stderr holds `needle` (true) or 120 s pass.
  bool waitFor(const std::string& needle) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline) {
      if (text_[0].find(needle) != std::string::npos || text_[1].find(needle) != std::string::npos)
        return true;
      if (!readSome(100)) return false;
    }
    return false;
  }
  // Waits for the end (at most 120 s, then SIGKILL), reading all output. The wait status.
  int wait() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) ::kill(pid_, SIGKILL);
      readSome(50);
    }
    while (readSome(0)) {
    }
    reaped_ = true;
    for (int& fd : fds_) {
      if (fd >= 0) ::close(fd);
      fd = -1;
    }
    return status;
  }

 private:
  // False once both streams are closed.
  bool readSome(int timeoutMs) {
    pollfd p[2] = {{fds_[0], POLLIN, 0}, {fds_[1], POLLIN, 0}};
    if (fds_[0] < 0 && fds_[1] < 0) return false;
    if (::poll(p, 2, timeoutMs) <= 0) return true;
    for (int i = 0; i < 2; ++i) {
      if (fds_[i] < 0 || !(p[i].revents & (POLLIN | POLLHUP))) continue;
      char buffer[4096];
      const ssize_t n = ::read(fds_[i], buffer, sizeof buffer);
      if (n > 0) {
        text_[i].append(buffer, std::size_t(n));
      } else {
        ::close(fds_[i]);
        fds_[i] = -1;
      }
    }
    return fds_[0] >= 0 || fds_[1] >= 0;
  }

  pid_t pid_ = -1;
  int fds_[2] = {-1, -1};
  std::string text_[2];
  bool reaped_ = false;
};

// A validate run that drills the built-in bone at 5 mm: a few seconds a case.
std::vector<std::string> validateArgs(const std::string& outDir) {
  return {"validate", "--quick", "--voxel-sizes", "5", "--out-dir", outDir};
}

class RunFolderCliTest : public CliTest {
 protected:
  // A complete set of an earlier validate run, as files of known bytes.
  std::map<std::string, std::string> writeOldValidateSet(const std::string& dir) const {
    const std::map<std::string, std::string> set = {
        {"report.json", "{\"old\": true}\n"},
        {"report.html", "<p>old</p>\n"},
        {"validate.log", "old log\n"},
        {"forces/default_5mm_static_portal-5.csv", "old forces\n"},
        {"plots/default_VS_5_mm_portal-5.png", "old plot"},
        {"images/0_crackfree/front.png", "old image"}};
    for (const auto& [name, bytes] : set) {
      fs::create_directories(fs::path(dir + "/" + name).parent_path());
      test::writeBytes(dir + "/" + name, bytes);
    }
    return set;
  }

  // The command with files limited to `bytes`, as a disk with that much room left: writes past
  // it fail with EFBIG (SIGXFSZ ignored, as the shell passes it on), as ENOSPC fails them.
  CliRun osteonOnSmallDisk(const std::string& args, rlim_t bytes) const {
    rlimit limit{};
    getrlimit(RLIMIT_FSIZE, &limit);
    const rlimit saved = limit;
    limit.rlim_cur = bytes;
    void (*oldHandler)(int) = std::signal(SIGXFSZ, SIG_IGN);
    setrlimit(RLIMIT_FSIZE, &limit);
    const CliRun run = osteon(args);
    setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, oldHandler);
    return run;
  }

  // Stops `child` with `signal` once `needle` shows it midway; expects the clean end.
  static void interrupt(Child& child, const std::string& needle, int signal, int exitCode) {
    ASSERT_TRUE(child.waitFor(needle)) << child.out() << child.err();
    ::kill(child.pid(), signal);
    const int status = child.wait();
    ASSERT_TRUE(WIFEXITED(status))
        << "ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
        << ", not by exiting cleanly\n"
        << child.err();
    EXPECT_EQ(WEXITSTATUS(status), exitCode) << child.err();
    // The last line says why (progress lines come before it).
    const std::string& err = child.err();
    const std::size_t last = err.rfind('\n', err.size() >= 2 ? err.size() - 2 : 0);
    const std::string line = err.substr(last == std::string::npos ? 0 : last + 1);
    EXPECT_EQ(
        line.rfind(
            std::string("osteon: interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM"), 0),
        0u)
        << err;
  }
};

TEST_F(RunFolderCliTest, ValidateStoppedBySigtermLeavesThePreviousSetWholeAndNoTemporaries) {
  const std::string dir = path("v");
  const std::map<std::string, std::string> old = writeOldValidateSet(dir);
  Child run(validateArgs(dir));
  interrupt(run, "[1/4]", SIGTERM, 143);  // a case done: its force logs were written
  EXPECT_EQ(filesIn(dir), old);
}

TEST_F(RunFolderCliTest, ADrillThatFailsAfterItsForceLogKeepsThePreviousSetWhole) {
  const std::string args = "drill default --voxel-size 1.2 --levels 0 --path portal-5 --out-dir ";
  ASSERT_EQ(osteon(args + quoted(path("full"))).exitCode, 0);
  const std::size_t forcesBytes = fs::file_size(path("full/forces.csv"));
  const std::size_t surfaceBytes = fs::file_size(path("full/surface.ply"));
  ASSERT_LT(forcesBytes + 1000, surfaceBytes) << "the surface must be the file that does not fit";
  const std::string dir = path("d");
  const std::map<std::string, std::string> old = {{"forces.csv", "old forces\n"},
                                                  {"summary.json", "{\"old\": true}\n"},
                                                  {"surface.ply", "old surface"}};
  fs::create_directories(dir);
  for (const auto& [name, bytes] : old) test::writeBytes(dir + "/" + name, bytes);
  // Room for the force log, not for the surface: the disk fills after the log was complete.
  const CliRun run = osteonOnSmallDisk(args + quoted(dir), (forcesBytes + surfaceBytes) / 2);
  EXPECT_EQ(run.exitCode, 2) << run.err;
  EXPECT_NE(run.err.find("surface.ply"), std::string::npos) << run.err;
  EXPECT_EQ(filesIn(dir), old) << "no new forces.csv beside the old summary and surface";
}

TEST_F(RunFolderCliTest, AThreadedDrillStoppedBySigintKeepsThePreviousSetAndNoPartialLog) {
  const std::string dir = path("d");
  const std::map<std::string, std::string> old = {{"forces.csv", "old forces\n"},
                                                  {"summary.json", "{\"old\": true}\n"},
                                                  {"surface.ply", "old surface"}};
  fs::create_directories(dir);
  for (const auto& [name, bytes] : old) test::writeBytes(dir + "/" + name, bytes);
  // Seven seconds of path in real time: two seconds in, the loops are drilling.
  Child run({"drill", "default", "--voxel-size", "1.2", "--path", "portal-5", "--threaded",
             "--out-dir", dir});
  std::this_thread::sleep_for(std::chrono::seconds(2));
  interrupt(run, "", SIGINT, 130);
  EXPECT_EQ(filesIn(dir), old);
}

TEST_F(RunFolderCliTest, ExperimentStoppedBySigintLeavesNoFolderBehind) {
  const std::string dir = path("e");
  Child run({"experiment", "seed", "--out-dir", dir});
  interrupt(run, "jitter", SIGINT, 130);  // a run done: its force log was written
  EXPECT_EQ(filesIn(dir), (std::map<std::string, std::string>{}));
  EXPECT_FALSE(fs::exists(dir)) << "the run made the folder: it goes with the run";
}

TEST_F(RunFolderCliTest, AKilledRunsTemporariesAreRemovedByTheNextRunIntoTheFolder) {
  const std::string dir = path("v");
  Child killed(validateArgs(dir));
  ASSERT_TRUE(killed.waitFor("[1/4]")) << killed.err();
  ::kill(killed.pid(), SIGKILL);
  killed.wait();
  const std::string mark = ".tmp" + std::to_string(killed.pid()) + "-";
  const auto leftovers = [&] {
    std::size_t n = 0;
    for (const auto& [name, bytes] : filesIn(dir)) n += name.find(mark) != std::string::npos;
    return n;
  };
  ASSERT_GT(leftovers(), 0u) << "a killed run leaves its temporaries";
  // Any command's next run into the folder removes them (the process is gone).
  const CliRun next =
      osteon("drill default --voxel-size 1.2 --levels 0 --path portal-5 --out-dir " + quoted(dir));
  ASSERT_EQ(next.exitCode, 0) << next.err;
  EXPECT_EQ(leftovers(), 0u);
  EXPECT_TRUE(fs::exists(dir + "/forces.csv"));
}

TEST_F(RunFolderCliTest, ASecondRunIntoAFolderInUseIsRefusedNamingTheFirst) {
  const std::string dir = path("v");
  Child first(validateArgs(dir));
  ASSERT_TRUE(first.waitFor("[1/4]")) << first.err();
  const CliRun second = osteon("validate --quick --voxel-sizes 5 --out-dir " + quoted(dir));
  EXPECT_EQ(second.exitCode, 2) << second.out << second.err;
  EXPECT_TRUE(second.out.empty()) << second.out;
  EXPECT_EQ(second.err.find('\n'), second.err.size() - 1) << "one line: " << second.err;
  EXPECT_NE(second.err.find("--out-dir " + dir + ": another osteon run (process " +
                            std::to_string(first.pid()) + ") is writing into this folder"),
            std::string::npos)
      << second.err;
  // The same lock for every command that fills an --out-dir.
  const CliRun drill =
      osteon("drill default --voxel-size 1.2 --levels 0 --path portal-5 --out-dir " + quoted(dir));
  EXPECT_EQ(drill.exitCode, 2) << drill.err;
  EXPECT_NE(drill.err.find("(process " + std::to_string(first.pid()) + ")"), std::string::npos)
      << drill.err;
  // The first run goes on undisturbed to its report.
  const int status = first.wait();
  ASSERT_TRUE(WIFEXITED(status)) << first.err();
  EXPECT_EQ(WEXITSTATUS(status), 0) << first.err();
  EXPECT_TRUE(fs::exists(dir + "/report.json"));
  EXPECT_FALSE(fs::exists(dir + "/forces.csv")) << "the refused drill wrote nothing";
}

TEST_F(RunFolderCliTest, ModelsOfTheSameStemKeepTheirOwnForceLogsAndPlots) {
  fs::create_directories(path("big"));
  ASSERT_EQ(osteon("model --out " + quoted(path("big/default.obj"))).exitCode, 0);
  const std::string dir = path("v");
  const CliRun run = osteon("validate --quick --voxel-sizes 5 --models default," +
                            quoted(path("big/default.obj")) + " --out-dir " + quoted(dir));
  ASSERT_EQ(run.exitCode, 0) << run.out << run.err;
  // Four logs per model (static, dynamic x two portals) under two names.
  std::map<std::string, std::size_t> logsOf;
  for (const fs::directory_entry& e : fs::directory_iterator(dir + "/forces")) {
    const std::string name = e.path().filename().string();
    logsOf[name.substr(0, name.find("_5mm_"))] += 1;
  }
  ASSERT_EQ(logsOf.size(), 2u) << run.out;
  for (const auto& [model, logs] : logsOf) {
    EXPECT_EQ(logs, 4u) << model;
    EXPECT_EQ(model.rfind("default", 0), 0u) << "named by the stem first: " << model;
  }
  // Each plot draws its own model's logs.
  const std::string script = test::readBytes(dir + "/plots/plots.gp");
  std::size_t plots = 0;
  for (std::size_t at = script.find("set output '"); at != std::string::npos;
       at = script.find("set output '", at + 1)) {
    const std::string png =
        fs::path(script.substr(at + 12, script.find('\'', at + 12) - at - 12)).filename().string();
    const std::string model = png.substr(0, png.find("_VS_"));
    ASSERT_TRUE(logsOf.count(model)) << png;
    const std::string line =
        script.substr(script.find("plot ", at),
                      script.find('\n', script.find("plot ", at)) - script.find("plot ", at));
    EXPECT_NE(line.find("forces/" + model + "_5mm_static_"), std::string::npos) << line;
    for (const auto& [other, logs] : logsOf) {
      if (other != model) {
        EXPECT_EQ(line.find("forces/" + other + "_"), std::string::npos) << line;
      }
    }
    EXPECT_TRUE(fs::exists(dir + "/plots/" + png)) << png;
    ++plots;
  }
  EXPECT_EQ(plots, 4u);
  // The same names on every run (shards of one run must agree).
  const CliRun again = osteon("validate --quick --voxel-sizes 5 --models default," +
                              quoted(path("big/default.obj")) + " --out-dir " + quoted(path("v2")));
  ASSERT_EQ(again.exitCode, 0) << again.err;
  std::set<std::string> names, namesAgain;
  for (const fs::directory_entry& e : fs::directory_iterator(dir + "/forces"))
    names.insert(e.path().filename());
  for (const fs::directory_entry& e : fs::directory_iterator(path("v2/forces")))
    namesAgain.insert(e.path().filename());
  EXPECT_EQ(names, namesAgain);
}

TEST_F(RunFolderCliTest, AnExistingRecordingSurvivesARunThatFailsAfterRecordingStarted) {
  const std::string recording = path("hand.csv");
  const std::string old =
      "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on\n0,1,2,3,1,0,0,0,0,0,1\n0.001,1,2,3,1,0,0,0,0,0,"
      "1\n";
  test::writeBytes(recording, old);
  const std::string args =
      "drill default --voxel-size 1.2 --levels 0 --device scripted:portal-5 --record " +
      quoted(recording) + " --out-dir ";
  // A disk with 200 kB left: the force log fails after the recording began (as faults_cli_test).
  const CliRun failed = osteonOnSmallDisk(args + quoted(path("small")), 200000);
  EXPECT_EQ(failed.exitCode, 2) << failed.err;
  EXPECT_NE(failed.err.find("cannot write the force log"), std::string::npos) << failed.err;
  EXPECT_EQ(test::readBytes(recording), old) << "the old recording is kept whole";
  for (const auto& [name, bytes] : filesIn(path(""))) {
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << "temporary left: " << name;
  }
  // A run that succeeds replaces it with the new one.
  const CliRun ok = osteon(args + quoted(path("out")));
  ASSERT_EQ(ok.exitCode, 0) << ok.err;
  const std::string fresh = test::readBytes(recording);
  EXPECT_NE(fresh, old);
  EXPECT_GT(fresh.size(), old.size());
}

}  // namespace
}  // namespace osteon
