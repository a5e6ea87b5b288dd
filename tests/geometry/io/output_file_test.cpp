#include "osteon/geometry/io/output_file.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "support/files.h"
#include "support/shapes.h"

namespace osteon::geometry {
namespace {

namespace fs = std::filesystem;

std::size_t filesIn(const std::string& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const fs::directory_entry& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(OutputFile, ReplacesTheTargetOnlyOnCommit) {
  const std::string dir = test::makeTempDir("output_file");
  const std::string target = dir + "/out.txt";
  test::writeBytes(target, "old");
  {
    OutputFile file(target);
    EXPECT_EQ(fs::path(file.tempPath()).parent_path(), fs::path(target).parent_path());
    EXPECT_EQ(fs::path(file.tempPath()).extension(), ".txt");  // image writers go by it
    test::writeBytes(file.tempPath(), "new");
    EXPECT_EQ(test::readBytes(target), "old");
    file.commit();
  }
  EXPECT_EQ(test::readBytes(target), "new");
  {
    OutputFile abandoned(target);
    test::writeBytes(abandoned.tempPath(), "half");
  }  // a run that failed before commit
  EXPECT_EQ(test::readBytes(target), "new");
  EXPECT_EQ(filesIn(dir), 1u);
  writeFileAtomically(target, "whole");
  EXPECT_EQ(test::readBytes(target), "whole");
  EXPECT_EQ(filesIn(dir), 1u);
  EXPECT_THROW(OutputFile{dir}, InputError);  // a folder is not an output file
  EXPECT_THROW(writeFileAtomically(dir + "/no/such/folder/x.txt", "x"), InputError);
  fs::remove_all(dir);
}

TEST(OutputFile, RefusesOutputsThatAreInputsThroughLinks) {
  const std::string dir = test::makeTempDir("output_file");
  test::writeBytes(dir + "/in.stl", "mesh");
  fs::create_symlink(dir + "/in.stl", dir + "/soft.stl");
  fs::create_hard_link(dir + "/in.stl", dir + "/hard.stl");
  EXPECT_TRUE(sameFile(dir + "/in.stl", dir + "/./in.stl"));
  EXPECT_TRUE(sameFile(dir + "/soft.stl", dir + "/in.stl"));
  EXPECT_FALSE(sameFile(dir + "/in.stl", dir + "/missing.stl"));
  for (const char* out : {"/in.stl", "/soft.stl", "/hard.stl"}) {
    EXPECT_THROW(refuseOverwritingInputs({dir + out}, {dir + "/in.stl"}), InputError) << out;
  }
  EXPECT_NO_THROW(refuseOverwritingInputs({dir + "/new.stl", ""}, {dir + "/in.stl", ""}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace osteon::geometry
