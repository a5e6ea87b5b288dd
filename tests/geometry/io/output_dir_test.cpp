#include "osteon/geometry/io/output_dir.h"

#include <filesystem>
#include <map>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"
#include "osteon/geometry/io/output_file.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

// Every file below `dir`, hidden ones too, relative, with its bytes.
std::map<std::string, std::string> filesIn(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file())
      files[fs::relative(e.path(), dir).string()] = test::readBytes(e.path().string());
  }
  return files;
}

class OutputDirTest : public ::testing::Test {
 protected:
  std::string dir_ = test::makeTempDir("output_dir");
  void TearDown() override {
    gInterruptSignal.store(0);
    fs::remove_all(dir_);
  }
  // The previous run's set: a report, and logs in a folder the run owns.
  void writeOldSet() const {
    fs::create_directories(dir_ + "/logs");
    test::writeBytes(dir_ + "/report.txt", "old report");
    test::writeBytes(dir_ + "/logs/a.csv", "old a");
    test::writeBytes(dir_ + "/logs/b.csv", "old b");  // the new run writes no b
    test::writeBytes(dir_ + "/notes.txt", "the user's");
  }
};

TEST_F(OutputDirTest, OutputsGoInPlaceTogetherOnCommitAndTheRestOfThePreviousSetGoes) {
  writeOldSet();
  {
    OutputDir out(dir_, {"report.txt", "logs"});
    writeFileAtomically(dir_ + "/logs/a.csv", "new a");
    writeFileAtomically(dir_ + "/report.txt", "new report");
    // Held back: the old set is whole until the commit, and the run reads its own bytes.
    EXPECT_EQ(test::readBytes(dir_ + "/logs/a.csv"), "old a");
    EXPECT_EQ(test::readBytes(OutputDir::currentPath(dir_ + "/logs/a.csv")), "new a");
    EXPECT_EQ(OutputDir::currentPath(dir_ + "/notes.txt"), dir_ + "/notes.txt");
    out.commit();
  }
  EXPECT_EQ(filesIn(dir_), (std::map<std::string, std::string>{{"logs/a.csv", "new a"},
                                                               {"report.txt", "new report"},
                                                               {"notes.txt", "the user's"}}));
  // Outside an open folder, outputs go in place at once.
  writeFileAtomically(dir_ + "/report.txt", "later");
  EXPECT_EQ(test::readBytes(dir_ + "/report.txt"), "later");
}

TEST_F(OutputDirTest, ARunThatFailsOrIsInterruptedLeavesThePreviousSetAsItWas) {
  writeOldSet();
  const std::map<std::string, std::string> old = filesIn(dir_);
  {
    OutputDir out(dir_, {"report.txt", "logs"});
    fs::create_directories(dir_ + "/logs/new");
    writeFileAtomically(dir_ + "/logs/new/c.csv", "new c");
    writeFileAtomically(dir_ + "/report.txt", "new report");
  }  // no commit: a run that failed
  EXPECT_EQ(filesIn(dir_), old);
  EXPECT_FALSE(fs::exists(dir_ + "/logs/new")) << "the empty folder the run made goes too";
  {
    OutputDir out(dir_, {"report.txt", "logs"});
    writeFileAtomically(dir_ + "/report.txt", "new report");
    gInterruptSignal.store(SIGTERM);  // as the handler does
    try {
      out.commit();
      ADD_FAILURE() << "an interrupted run was put in place";
    } catch (const Interrupted& e) {
      EXPECT_EQ(e.exitCode(), 143);
    }
  }
  EXPECT_EQ(filesIn(dir_), old);
}

TEST_F(OutputDirTest, AFolderItMadeGoesWithAFailedRun) {
  const std::string fresh = dir_ + "/fresh";
  {
    OutputDir out(fresh, {"x.txt"});
    writeFileAtomically(fresh + "/x.txt", "x");
  }
  EXPECT_FALSE(fs::exists(fresh));
}

TEST_F(OutputDirTest, TemporariesOfADeadProcessAreRemovedWhenTheFolderIsOpened) {
  // A process that has ended: its id names no live process now (reaped).
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  const std::string dead = ".tmp" + std::to_string(child) + "-3";
  const std::string alive = ".tmp" + std::to_string(::getppid()) + "-0";
  fs::create_directories(dir_ + "/runs/r1");
  test::writeBytes(dir_ + "/.report" + dead + ".txt", "leftover");
  test::writeBytes(dir_ + "/runs/r1/.forces" + dead + ".csv", "leftover");
  test::writeBytes(dir_ + "/.other" + alive + ".txt", "a live process's");
  test::writeBytes(dir_ + "/.profile.tmp", "not a temporary of ours");
  { OutputDir out(dir_); }  // any run, whatever it owns
  EXPECT_EQ(filesIn(dir_),
            (std::map<std::string, std::string>{{".other" + alive + ".txt", "a live process's"},
                                                {".profile.tmp", "not a temporary of ours"}}));
}

TEST_F(OutputDirTest, ASecondRunIntoTheFolderIsRefusedNamingTheFirst) {
  OutputDir first(dir_);
  // Another process (the lock is per open folder, as two runs hold it).
  const pid_t child = ::fork();
  if (child == 0) {
    int code = 1;
    try {
      OutputDir second(dir_);
    } catch (const InputError& e) {
      const std::string what = e.what();
      code = what.find("another osteon run (process " + std::to_string(::getppid()) + ")") !=
                     std::string::npos
                 ? 0
                 : 2;
    } catch (...) {
      code = 3;
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: not refused, 2: refused without naming the first run";
}

}  // namespace
}  // namespace osteon::geometry
