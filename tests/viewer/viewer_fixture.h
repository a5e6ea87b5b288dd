// osteon-viewer run under Xvfb, as the viewer's window tests run it: each test in a folder of its
// own, skipped with the reason when Xvfb (or, for tests that type and click, xdotool) is missing
// (scripts/setup installs both). Set OSTEON_VIEWER_SHOTS=DIR to keep the screenshots.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "support/files.h"
#include "support/process.h"

namespace osteon::test {

class ViewerFixture : public ::testing::Test {
 protected:
  explicit ViewerFixture(const std::string& name, bool needsInput = false)
      : dir_(makeTempDir(name)), needsInput_(needsInput) {}

  void SetUp() override {
    if (!xvfbWorks())
      GTEST_SKIP()
          << "no X server: xvfb-run is missing or Xvfb cannot start (scripts/setup installs xvfb)";
    if (needsInput_ && !xdotoolWorks())
      GTEST_SKIP() << "no X input: xdotool is missing (scripts/setup installs it)";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

  // `program args` in a 1280x800 virtual screen (window), or with no display at all.
  ProcessRun runProgram(const std::string& program, const std::string& args,
                        bool window = true) const {
    const std::string prefix =
        window ? "xvfb-run -a -s '-screen 0 1280x800x24' " : "env -u DISPLAY ";
    return runShell(prefix + "timeout 300 '" + program + "' " + args, path("stdout"),
                    path("stderr"));
  }
  ProcessRun run(const std::string& args, bool window = true) const {
    return runProgram(OSTEON_VIEWER, args, window);
  }
  // The screenshot `png` of this test's folder copied to OSTEON_VIEWER_SHOTS, when it is set.
  void keepShot(const std::string& png) const {
    if (const char* keep = std::getenv("OSTEON_VIEWER_SHOTS")) {
      std::filesystem::create_directories(keep);
      std::filesystem::copy_file(path(png), std::string(keep) + "/" + png,
                                 std::filesystem::copy_options::overwrite_existing);
    }
  }

  std::string dir_;

 private:
  static bool xvfbWorks() {
    static const bool works =
        std::system("command -v xvfb-run >/dev/null 2>&1 && xvfb-run -a true >/dev/null 2>&1") == 0;
    return works;
  }
  static bool xdotoolWorks() {
    static const bool works = std::system("command -v xdotool >/dev/null 2>&1") == 0;
    return works;
  }
  bool needsInput_;
};

}  // namespace osteon::test
