// The crack views as a folder of PNG files: the six written as one set, the previous set kept
// until the new one is complete, and an input in the folder refused before any work.
#include "osteon/validation/crack_images.h"

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon::validation {
namespace {

TEST(CrackImages, AFolderHoldsTheSixViewsOfTheLastSurfaceWritten) {
  const std::string dir = test::makeTempDir("crack_images") + "/views";
  std::vector<std::string> paths;
  {
    CrackImageFolder folder(dir, "--images");
    const CrackMetric metric = folder.write(test::makeSphere(5.0, 32, 16), 64, paths);
    EXPECT_EQ(metric.pixels, 64);
    EXPECT_GT(metric.white, 0u);
  }
  ASSERT_EQ(paths.size(), 6u);
  const std::vector<std::string> names = crackImageNames();
  for (std::size_t i = 0; i < paths.size(); ++i) {
    EXPECT_EQ(paths[i], dir + "/" + names[i]);
    EXPECT_EQ(test::readBytes(paths[i]).substr(1, 3), "PNG") << paths[i];
  }
  // A folder claimed and left without a write keeps the set it held.
  const std::string before = test::readBytes(paths.front());
  { CrackImageFolder unused(dir, "--images"); }
  EXPECT_EQ(test::readBytes(paths.front()), before);
}

TEST(CrackImages, AnInputWhereAViewGoesIsRefusedBeforeAnyWork) {
  const std::string dir = test::makeTempDir("crack_images_input");
  const std::string input = dir + "/cracks_+x.png";
  test::writeBytes(input, "not an image, an input");
  EXPECT_THROW(CrackImageFolder::refuseOverwriting(dir, {input}), InputError);
  EXPECT_NO_THROW(CrackImageFolder::refuseOverwriting(dir, {dir + "/mesh.stl"}));
  EXPECT_EQ(test::readBytes(input), "not an image, an input");
}

TEST(CrackImages, ARunsOwnFolderIsCreatedForItsViews) {
  const std::string dir = test::makeTempDir("crack_images_run") + "/images/0_crackfree";
  const std::vector<std::string> paths = writeCrackImagesOf(test::makeSphere(5.0, 32, 16), 32, dir);
  ASSERT_EQ(paths.size(), 6u);
  for (const std::string& p : paths) EXPECT_TRUE(std::filesystem::exists(p)) << p;
}

}  // namespace
}  // namespace osteon::validation
