// A test's own folder of volumes, and what osteon's volume loader says of one of them.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/files.h"

namespace osteon::test {

class VolumeFolderTest : public ::testing::Test {
 protected:
  explicit VolumeFolderTest(const std::string& name) : dir_(makeTempDir(name)) {}
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string file(const std::string& name) const { return dir_ + "/" + name; }

  // The message loadVolume refuses `name` with ("" if it loads).
  std::string refusal(const std::string& name, const geometry::VolumeOptions& options = {}) const {
    try {
      geometry::loadVolume(file(name), options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  std::string dir_;
};

}  // namespace osteon::test
