// The offline WAV: its header, its samples in the run's time, the same bytes for the same
// frames, and a path that cannot be written refused by name.
#include "osteon/audio/wav_writer.h"

#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "support/allocation_counter.h"
#include "support/files.h"
#include "support/wav_spectrum.h"

namespace osteon::audio {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void record(const std::string& path, int rows) {
  WavRecording wav(path);
  for (int i = 1; i <= rows; ++i) {
    wav.add({i * 1e-3, 1000.0, i > rows / 2 ? 10.0 : 0.0, i > rows / 2 ? 1.0 : 0.0, true});
  }
  wav.finish();
}

TEST(WavRecording, SamplesInTheRunsTimeSameBytesEveryRun) {
  const std::string dir = test::makeTempDir("wav");
  record(dir + "/a.wav", 1500);
  record(dir + "/b.wav", 1500);
  const test::WavSamples w = test::readWav(dir + "/a.wav");
  EXPECT_EQ(w.rateHz, 44100u);
  EXPECT_EQ(w.samples.size(), static_cast<std::size_t>(std::llround(1.5 * 44100)));
  EXPECT_EQ(slurp(dir + "/a.wav"), slurp(dir + "/b.wav"));
  EXPECT_EQ(slurp(dir + "/a.wav").size(), 44 + 2 * w.samples.size());
  std::filesystem::remove_all(dir);
}

// The rows reach the sound inside the force log's write(), which allocates nothing.
TEST(WavRecording, AddingRowsAllocatesNothing) {
  const std::string dir = test::makeTempDir("wav");
  WavRecording wav(dir + "/rows.wav");
  const std::uint64_t before = test::threadAllocations();
  for (int i = 1; i <= 3000; ++i) wav.add({i * 1e-3, 1500.0, 20.0, 2.0, true});
  EXPECT_EQ(test::threadAllocations(), before);
  wav.finish();
  std::filesystem::remove_all(dir);
}

TEST(WavWriter, HeaderSaysMono16BitPcm) {
  const auto h = wavHeader(44100, 10);
  EXPECT_EQ(std::string(h.begin(), h.begin() + 4), "RIFF");
  EXPECT_EQ(h[4], 36 + 20);
  EXPECT_EQ(std::string(h.begin() + 8, h.begin() + 16), "WAVEfmt ");
  EXPECT_EQ(h[22], 1);   // one channel
  EXPECT_EQ(h[34], 16);  // bits
  EXPECT_EQ(h[40], 20);  // data bytes
}

TEST(WavWriter, UnwritablePathNamed) {
  try {
    WavWriter w("/nonexistent-folder/x.wav", 44100);
    FAIL() << "opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder/x.wav"), std::string::npos);
  }
}

}  // namespace
}  // namespace osteon::audio
