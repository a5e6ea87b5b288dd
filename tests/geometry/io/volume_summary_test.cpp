// A volume's values are summarised in pieces of 2^20 values in parallel: the distinct values, the
// most common one and the range must be those of the whole volume whichever piece holds them.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/geometry/io/volume_io.h"
#include "support/volume_files.h"
#include "support/volume_fixture.h"

namespace osteon::geometry {
namespace {

using test::TestVolume;

class VolumeSummary : public test::VolumeFolderTest {
 protected:
  VolumeSummary() : VolumeFolderTest("volume_summary") {}

  // 160 x 128 x 128 uint8 (2.6 M values: three pieces), value 9 throughout but where given.
  TestVolume spanningPieces() const {
    TestVolume v;
    v.sizes = {160, 128, 128};
    v.values.assign(std::size_t(160) * 128 * 128, 9.0);
    return v;
  }
};

constexpr std::size_t kPiece = std::size_t(1) << 20;

TEST_F(VolumeSummary, DistinctValuesSplitAcrossPiecesAreCountedOnce) {
  // 64 distinct values: 0..39 in the first piece, 30..62 in the second (a shared 30..39), and
  // 9 everywhere: a label map of 64 labels, the most common (9) its background as 0 is present.
  TestVolume v = spanningPieces();
  for (int k = 0; k < 40; ++k) v.values[std::size_t(1000 + 3 * k)] = k;
  for (int k = 30; k < 63; ++k) v.values[kPiece + std::size_t(5 * k)] = k;
  v.values[2 * kPiece + 17] = 63;
  test::writeTestNrrd(file("labels.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values),
                      false);
  const VolumeLoad load = loadVolume(file("labels.nrrd"));
  EXPECT_EQ(load.kind, "label map");
  EXPECT_EQ(load.labels.size(), 64u);
  EXPECT_EQ(load.labels.front(), 0u);
  EXPECT_EQ(load.labels.back(), 63u);
  EXPECT_EQ(load.background, 0u);
  EXPECT_DOUBLE_EQ(load.minValue, 0.0);
  EXPECT_DOUBLE_EQ(load.maxValue, 63.0);

  // One more distinct value in the last piece, each piece below the limit alone: not labels.
  v.values[2 * kPiece + 99] = 200;
  test::writeTestNrrd(file("many.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values), false);
  const std::string m = refusal("many.nrrd");
  EXPECT_NE(m.find("more than 64 distinct values"), std::string::npos) << m;
}

// A label map with these labels (ascending: its values run from the first to the last) and
// this background.
void expectLabelMap(const VolumeLoad& load, const std::vector<std::uint64_t>& labels,
                    std::uint64_t background) {
  EXPECT_EQ(load.kind, "label map");
  EXPECT_EQ(load.labels, labels);
  EXPECT_EQ(load.background, background);
  EXPECT_DOUBLE_EQ(load.minValue, double(labels.front()));
  EXPECT_DOUBLE_EQ(load.maxValue, double(labels.back()));
}

TEST_F(VolumeSummary, TheMostCommonValueIsCountedOverEveryPiece) {
  // No 0: the background is the most common value over the whole volume (5), though the first
  // piece holds mostly 9.
  TestVolume v = spanningPieces();
  for (std::size_t i = kPiece; i < v.values.size(); ++i) v.values[i] = i % 2 ? 5.0 : 6.0;
  for (std::size_t i = 0; i < v.values.size(); i += 3) v.values[i] = 5.0;
  test::writeTestNrrd(file("background.nrrd"), v, "uint8", test::encodeAs<std::uint8_t>(v.values),
                      false);
  expectLabelMap(loadVolume(file("background.nrrd")), {5, 6, 9}, 5);
}

TEST_F(VolumeSummary, SixteenBitValuesAreCountedInRunsAndOneByOne) {
  // uint16 labels at the top of the range: long runs of 65535 (counted a block at once), 40000
  // in every third voxel of the last pieces (one by one), and a single 1; no 0, so the
  // background is the most common value over the whole volume.
  TestVolume v = spanningPieces();
  for (std::size_t i = 0; i < v.values.size(); ++i) v.values[i] = 65535.0;
  for (std::size_t i = kPiece; i < v.values.size(); i += 3) v.values[i] = 40000.0;
  v.values[123] = 1.0;
  test::writeTestNrrd(file("wide.nrrd"), v, "uint16", test::encodeAs<std::uint16_t>(v.values),
                      false);
  expectLabelMap(loadVolume(file("wide.nrrd")), {1, 40000, 65535}, 65535);
}

}  // namespace
}  // namespace osteon::geometry
