// What a volume's values mean, through the command line: --iso must be finite, 64-bit labels
// print and select exactly, a label map's background, signed volumes of few values read as
// CTs, and a volume that would be bone everywhere refused.
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli_fixture.h"
#include "support/volume_files.h"

namespace osteon {
namespace {

using test::TestVolume;

std::string quoted(const std::string& s) {
  return "'" + s + "'";
}

TestVolume cube(int n, double value) {
  TestVolume v;
  v.sizes = {n, n, n};
  v.values.assign(std::size_t(n) * std::size_t(n) * std::size_t(n), value);
  return v;
}

template <typename T>
std::string bytesOf(const std::vector<T>& values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(&bytes[0], values.data(), bytes.size());
  return bytes;
}

class VolumeValuesCliTest : public CliTest {
 protected:
  nlohmann::json runJson(const std::string& args) const {
    const CliRun run = osteon(args);
    EXPECT_EQ(run.exitCode, 0) << args << "\n" << run.err;
    return run.out.empty() ? nlohmann::json() : nlohmann::json::parse(run.out);
  }
};

TEST_F(VolumeValuesCliTest, AnIsoLevelThatIsNotAFiniteNumberIsBadInput) {
  // A CT the iso level would otherwise make empty (nan, inf, 1e400) or all bone (-inf).
  const std::string ct = std::string(OSTEON_SOURCE_DIR) + "/tests/data/seeds/ct.nii";
  for (const std::string iso : {"nan", "inf", "-inf", "1e400"}) {
    SCOPED_TRACE(iso);
    for (const std::string command : {"mesh", "hierarchy"}) {
      expectBadInput(command + " " + quoted(ct) + " --iso " + iso + " --json", "--iso ",
                     "must be a finite number (HU for a CT");
    }
    expectBadInput("drill " + quoted(ct) + " --voxel-size 2 --path portal-5 --iso " + iso +
                       " --out-dir " + quoted(path("d")),
                   "--iso ", "must be a finite number (HU for a CT");
  }
  EXPECT_EQ(osteon("mesh " + quoted(ct) + " --iso 250 --json").exitCode, 0);
}

TEST_F(VolumeValuesCliTest, SixtyFourBitLabelsPrintAndSelectExactly) {
  // uint64: 2^64 - 1 prints as itself and --label can name it.
  const std::uint64_t top = std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint64_t> u(512, 0);
  for (int i = 100; i < 130; ++i) u[std::size_t(i)] = top;
  u[300] = 7;
  const TestVolume v = cube(8, 0.0);
  test::writeTestNrrd(path("u64.nrrd"), v, "uint64", bytesOf(u), true);
  const nlohmann::json j =
      runJson("mesh " + quoted(path("u64.nrrd")) + " --label 18446744073709551615 --json");
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j["volume"]["labels"].dump(), "[0,7,18446744073709551615]");
  EXPECT_EQ(j["volume"]["bone_label"].dump(), "18446744073709551615");
  EXPECT_EQ(j["volume"]["max"].dump(), "18446744073709551615");
  EXPECT_EQ(j["voxels_inside"].get<int>(), 30);
  const CliRun text = osteon("mesh " + quoted(path("u64.nrrd")) + " --label 18446744073709551615");
  EXPECT_NE(text.out.find("labels 0 7 18446744073709551615; bone: label 18446744073709551615"),
            std::string::npos)
      << text.out;
  // A negative label is no label (CLI11 would read -1 as 2^64 - 1).
  expectBadInput("mesh " + quoted(path("u64.nrrd")) + " --label -1", "--label",
                 "must be a non-negative integer");

  // int64: 2^53 and 2^53 + 1 are two labels, not one.
  const std::int64_t big = std::int64_t(1) << 53;
  std::vector<std::int64_t> s(512, 0);
  for (int i = 100; i < 130; ++i) s[std::size_t(i)] = big;
  s[300] = big + 1;
  test::writeTestNifti(path("i64.nii"), v, 1024, 64, bytesOf(s), false);
  const nlohmann::json all = runJson("hierarchy " + quoted(path("i64.nii")) + " --json");
  EXPECT_EQ(all["volume"]["labels"].dump(), "[0,9007199254740992,9007199254740993]");
  EXPECT_EQ(all["voxels"].get<int>(), 31);
  const nlohmann::json one =
      runJson("hierarchy " + quoted(path("i64.nii")) + " --label 9007199254740993 --json");
  EXPECT_EQ(one["voxels"].get<int>(), 1);
}

TEST_F(VolumeValuesCliTest, ALabelMapWithoutZeroHasItsMostCommonValueAsBackground) {
  TestVolume v = cube(8, 3.0);
  for (int z = 2; z < 6; ++z) {
    for (int y = 2; y < 6; ++y) {
      for (int x = 2; x < 6; ++x) v.values[std::size_t((z * 8 + y) * 8 + x)] = 9.0;
    }
  }
  test::writeTestNrrd(path("l.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), true);
  const nlohmann::json j = runJson("mesh " + quoted(path("l.nrrd")) + " --json");
  EXPECT_EQ(j["voxels_inside"].get<int>(), 64);
  EXPECT_EQ(j["volume"]["background"].get<int>(), 3);
  EXPECT_EQ(j["volume"]["bone_label"], "every non-background");
  const CliRun text = osteon("mesh " + quoted(path("l.nrrd")));
  EXPECT_NE(
      text.out.find("bone: every voxel but the background 3 (0 absent: the most common value)"),
      std::string::npos)
      << text.out;
  // One label everywhere, named: the whole box would be bone.
  const TestVolume same = cube(8, 4.0);
  test::writeTestNrrd(path("same.nrrd"), same, "uint8", test::encodeAs<std::uint8_t>(same.values),
                      false);
  expectBadInput("mesh " + quoted(path("same.nrrd")) + " --label 4", path("same.nrrd"),
                 "every voxel is bone: read as a label map (uint8, labels 4), bone = --label 4");
  const CliRun empty = osteon("mesh " + quoted(path("same.nrrd")) + " --json");
  EXPECT_EQ(empty.exitCode, 1) << "its one value is its background: no bone";
}

TEST_F(VolumeValuesCliTest, ASignedVolumeOfTwoValuesIsACtWhateverItsMajority) {
  // +-1000 HU with bone the majority (7^3 of 8^3): bone is the +1000 voxels, not the air.
  TestVolume v = cube(8, -1000.0);
  for (int z = 0; z < 7; ++z) {
    for (int y = 0; y < 7; ++y) {
      for (int x = 0; x < 7; ++x) v.values[std::size_t((z * 8 + y) * 8 + x)] = 1000.0;
    }
  }
  test::writeTestNrrd(path("pm.nrrd"), v, "short", test::encodeAs<std::int16_t>(v.values), true);
  const nlohmann::json j = runJson("mesh " + quoted(path("pm.nrrd")) + " --json");
  EXPECT_EQ(j["volume"]["kind"], "ct");
  EXPECT_EQ(j["voxels_inside"].get<int>(), 343);
  // All air: said, not the whole box as bone.
  const TestVolume air = cube(8, -1024.0);
  test::writeTestNrrd(path("air.nrrd"), air, "short", test::encodeAs<std::int16_t>(air.values),
                      true);
  expectBadInput("mesh " + quoted(path("air.nrrd")), path("air.nrrd"),
                 "neither a label map nor a CT");
  // An iso level below every value: the whole box would be bone.
  expectBadInput("mesh " + quoted(path("pm.nrrd")) + " --iso -5000", path("pm.nrrd"),
                 "every voxel is bone: read as a CT");
}

}  // namespace
}  // namespace osteon
