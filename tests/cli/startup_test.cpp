// Start-up: commands that write no image never load OpenImageIO (and its ~250 shared
// libraries); commands that do load it through the osteon::image plugin and still write real
// PNGs; a missing plugin is a one-line error only where an image is wanted.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "osteon/geometry/io/mesh_io.h"
#include "support/cli_fixture.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon {
namespace {

// Sets an environment variable for the commands run while it lives (they inherit it).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      ::setenv(name_, old_->c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

// What the dynamic loader reported while a command ran (LD_DEBUG=libs, one file per process:
// the shell, timeout and osteon; only osteon links anything but libc).
struct LoaderLog {
  CliRun run;
  std::string log;
};

class StartupTest : public CliTest {
 protected:
  LoaderLog withLoaderLog(const std::string& args) const {
    const std::string prefix = path("ld");
    LoaderLog result;
    {
      const ScopedEnv debug("LD_DEBUG", "libs");
      const ScopedEnv output("LD_DEBUG_OUTPUT", prefix);
      result.run = osteon(args);
    }
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
      if (entry.path().filename().string().rfind("ld.", 0) != 0) continue;
      result.log += test::readBytes(entry.path().string());
      std::filesystem::remove(entry.path());
    }
    return result;
  }
  // True when the loader initialised a library whose path contains `library`.
  static bool loaded(const LoaderLog& l, const std::string& library) {
    for (std::size_t at = l.log.find("calling init: "); at != std::string::npos;
         at = l.log.find("calling init: ", at + 1)) {
      const std::size_t end = l.log.find('\n', at);
      if (l.log.substr(at, end - at).find(library) != std::string::npos) return true;
    }
    return false;
  }
  std::string sphere() const {
    geometry::writeMesh(test::makeSphere(5.0, 32, 16), path("sphere.stl"));
    return path("sphere.stl");
  }
};

TEST_F(StartupTest, CommandsThatWriteNoImageNeverLoadOpenImageIO) {
  const std::string mesh = sphere();
  const std::string commands[] = {"--help", "info default", "info '" + mesh + "' --json",
                                  "check '" + mesh + "' --cracks 32 --json"};
  for (const std::string& args : commands) {
    const LoaderLog l = withLoaderLog(args);
    EXPECT_EQ(l.run.exitCode, 0) << args << "\n" << l.run.err;
    // The loader log must be there (else the test proves nothing), and name the libraries we
    // do link, but never OpenImageIO or the image plugin.
    ASSERT_TRUE(loaded(l, "libembree3")) << args << ": no loader log\n" << l.log.substr(0, 2000);
    EXPECT_FALSE(loaded(l, "libOpenImageIO")) << args;
    EXPECT_FALSE(loaded(l, "libosteon_image")) << args;
  }
}

// GDCM's initialisers cost about 40 ms: only a command that reads DICOM loads it.
TEST_F(StartupTest, OnlyCommandsThatReadDicomLoadGdcm) {
  const std::string seeds = std::string(OSTEON_SOURCE_DIR) + "/tests/data/seeds/";
  for (const std::string& args : {std::string("--help"), std::string("info default"),
                                  "mesh '" + seeds + "volume.mha' --json"}) {
    const LoaderLog l = withLoaderLog(args);
    EXPECT_EQ(l.run.exitCode, 0) << args << "\n" << l.run.err;
    ASSERT_TRUE(loaded(l, "libembree3")) << args << ": no loader log";
    EXPECT_FALSE(loaded(l, "libgdcm")) << args;
    EXPECT_FALSE(loaded(l, "libosteon_dicom")) << args;
  }
  const LoaderLog dicom = withLoaderLog("mesh '" + seeds + "volume.dcm' --json");
  EXPECT_EQ(dicom.run.exitCode, 0) << dicom.run.err;
  EXPECT_TRUE(loaded(dicom, "libosteon_dicom"));
  EXPECT_TRUE(loaded(dicom, "libgdcmMSFF"));
}

TEST_F(StartupTest, HelpStaysSmall) {
  // Peak RSS of `osteon --help`, as /usr/bin/time measures it (135 MB with OpenImageIO linked).
  if (!std::filesystem::exists("/usr/bin/time")) GTEST_SKIP() << "no /usr/bin/time";
  const std::string rss = path("rss");
  const std::string command = std::string("/usr/bin/time -f %M -o '") + rss + "' '" + OSTEON_CLI +
                              "' --help >/dev/null 2>&1 </dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream in(rss);
  long kilobytes = 0;
  ASSERT_TRUE(in >> kilobytes) << test::readBytes(rss);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  // The sanitizer's run-time (shadow memory, allocator) adds tens of MB of its own at start-up;
  // OpenImageIO would still add its ~95 MB on top.
  const long limitKb = 100 * 1024;
#else
  const long limitKb = 40 * 1024;
#endif
  EXPECT_LT(kilobytes, limitKb) << "osteon --help peaked at " << kilobytes << " KB";
}

TEST_F(StartupTest, CheckWithImagesLoadsThePluginAndWritesPngs) {
  const std::string images = path("images");
  const LoaderLog l =
      withLoaderLog("check '" + sphere() + "' --cracks 32 --images '" + images + "' --json");
  ASSERT_EQ(l.run.exitCode, 0) << l.run.err;
  EXPECT_TRUE(loaded(l, "libosteon_image")) << "the plugin writes the images";
  EXPECT_TRUE(loaded(l, "libOpenImageIO"));
  for (const char* side : {"+x", "-x", "+y", "-y", "+z", "-z"}) {
    const std::string file = images + "/cracks_" + side + ".png";
    ASSERT_TRUE(std::filesystem::is_regular_file(file)) << file;
    const std::string bytes = test::readBytes(file);
    ASSERT_GT(bytes.size(), 8u + 25u + 12u) << file;  // signature, IHDR, IEND at least
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << file;
    EXPECT_EQ(bytes.substr(12, 4), "IHDR") << file;
    // IHDR width and height, big-endian: 32 x 32 as --cracks asked.
    EXPECT_EQ(bytes.substr(16, 8), std::string("\0\0\0\x20\0\0\0\x20", 8)) << file;
    EXPECT_EQ(bytes.substr(bytes.size() - 8, 4), "IEND") << file;
  }
  // No temporary file is left beside them.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(images)) ++files;
  EXPECT_EQ(files, 6);
}

TEST_F(StartupTest, AMissingPluginIsAOneLineErrorOnlyWhereImagesAreWritten) {
  const ScopedEnv plugin("OSTEON_IMAGE_PLUGIN", path("nowhere/libosteon_image.so"));
  const std::string mesh = sphere();
  // Commands that write no image do not need it.
  const CliRun info = osteon("info '" + mesh + "'");
  EXPECT_EQ(info.exitCode, 0) << info.err;
  const CliRun check = osteon("check '" + mesh + "' --cracks 32");
  EXPECT_EQ(check.exitCode, 0) << check.err;
  // Writing images does: exit 2, one line naming the plugin and where it was looked for.
  expectBadInput("check '" + mesh + "' --cracks 32 --images '" + path("images") + "'",
                 "libosteon_image.so", path("nowhere/libosteon_image.so"));
}

}  // namespace
}  // namespace osteon
