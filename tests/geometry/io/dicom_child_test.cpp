// DICOM reads in a child process (geometry/src/io/dicom_child.h): what the child decodes is
// handed over intact, a child that aborts or stops making progress is refused in one line while
// a slow one that keeps beating is not; slices decoded in parallel report the first bad slice in
// stack order, every time.
#include "io/dicom_child.h"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "osteon/core/error.h"
#include "osteon/geometry/io/volume_io.h"
#include "support/dicom_series.h"
#include "support/files.h"

namespace osteon::geometry {
namespace {

using io::callDicomPlugin;
using io::DicomCallResult;
using Clock = std::chrono::steady_clock;

void pause(double seconds) {
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

// The refusal callDicomPlugin throws for `call` (quiet for `quietSeconds`), or "(returned)".
std::string refusal(const io::DicomPluginCall& call, double quietSeconds = 30.0) {
  std::vector<unsigned char> data;
  try {
    callDicomPlugin("series", false, data, call, quietSeconds);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(returned)";
}

TEST(DicomChild, DecodedBytesAndTheVolumeAreHandedOverIntact) {
  // 40 MB: more than two of the chunks the bytes are taken in.
  constexpr std::size_t kBytes = 40u << 20;
  std::vector<unsigned char> data;
  const DicomCallResult r =
      callDicomPlugin("series", false, data,
                      [](osteon_dicom_volume* out, osteon_dicom_alloc_fn alloc,
                         osteon_dicom_progress_fn progress, void* context, char*, std::size_t) {
                        out->sizes[0] = 7;
                        std::strcpy(out->series_uid, "1.2.3");
                        auto* to = static_cast<unsigned char*>(alloc(context, kBytes));
                        if (!to) return 3;
                        for (std::size_t i = 0; i < kBytes; ++i)
                          to[i] = static_cast<unsigned char>(i * 7 + i / 997);
                        progress(context, 0);
                        return 0;
                      });
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.volume.sizes[0], 7);
  EXPECT_STREQ(r.volume.series_uid, "1.2.3");
  ASSERT_EQ(data.size(), kBytes);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < kBytes; ++i)
    wrong += data[i] != static_cast<unsigned char>(i * 7 + i / 997);
  EXPECT_EQ(wrong, 0u);
}

TEST(DicomChild, ThePluginsRefusalsComeBackAsItGaveThem) {
  std::vector<unsigned char> data;
  const DicomCallResult r = callDicomPlugin(
      "series", true, data,
      [](osteon_dicom_volume* out, osteon_dicom_alloc_fn alloc, osteon_dicom_progress_fn,
         void* context, char* errbuf, std::size_t errlen) {
        for (int& s : out->sizes) s = 100000;  // far past any machine's memory
        std::strcpy(out->type, "int16");
        if (alloc(context, 1)) return 0;
        std::snprintf(errbuf, errlen, "no memory for the volume");
        return 3;
      });
  EXPECT_EQ(r.code, 3);
  EXPECT_EQ(r.error, "no memory for the volume");
  EXPECT_EQ(r.refusal.rfind("series: ", 0), 0u) << r.refusal;
  EXPECT_TRUE(data.empty());
}

TEST(DicomChild, AChildThatAbortsIsRefusedInOneLine) {
  const std::string message =
      refusal([](osteon_dicom_volume*, osteon_dicom_alloc_fn, osteon_dicom_progress_fn, void*,
                 char*, std::size_t) -> int { std::abort(); });
  EXPECT_EQ(message.rfind("series: GDCM aborted reading it (", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(DicomChild, AHungReadIsKilledAndASlowOneThatBeatsIsNot) {
  const auto start = Clock::now();
  const std::string hung = refusal(
      [](osteon_dicom_volume*, osteon_dicom_alloc_fn, osteon_dicom_progress_fn, void*, char*,
         std::size_t) {
        pause(20.0);
        return 0;
      },
      0.3);
  EXPECT_EQ(hung, "series: GDCM made no progress reading it for 0.3 s (a hung read)");
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 5.0);
  // Ten beats 0.1 s apart: a second in all, three times the quiet allowed.
  EXPECT_EQ(refusal(
                [](osteon_dicom_volume*, osteon_dicom_alloc_fn, osteon_dicom_progress_fn progress,
                   void* context, char*, std::size_t) {
                  for (int i = 0; i < 10; ++i) {
                    pause(0.1);
                    progress(context, 0);
                  }
                  return 0;
                },
                0.3),
            "(returned)");
  // A step announced as 2 million pixels is allowed 2 s more.
  EXPECT_EQ(refusal(
                [](osteon_dicom_volume*, osteon_dicom_alloc_fn, osteon_dicom_progress_fn progress,
                   void* context, char*, std::size_t) {
                  progress(context, 2000000);
                  pause(1.0);
                  return 0;
                },
                0.3),
            "(returned)");
}

// Slices 9 and 31 of 40 are wider than the rest: the refusal names slice 9 whichever thread
// reaches a bad slice first.
TEST(DicomChild, ParallelSlicesReportTheFirstBadSliceInStackOrder) {
  const std::string dir = test::makeTempDir("dicom_child");
  std::vector<test::DicomSlice> slices = test::dicomStack(40, 0.0, 1.0, 32, 32);
  for (const int k : {9, 31}) {
    test::DicomSlice& s = slices[std::size_t(k)];
    s.columns = 33;
    s.stored.resize(std::size_t(s.columns * s.rows), 0);
  }
  for (std::size_t k = 0; k < slices.size(); ++k) {
    slices[k].transferSyntax = "jpegls";
    test::writeDicomSlice(dir + "/S" + std::to_string(k) + ".dcm", slices[k]);
  }
  for (int run = 0; run < 4; ++run) {
    try {
      readRawVolume(dir, VolumeOptions{});
      ADD_FAILURE() << "read";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), dir + ": S9.dcm: 33 x 32 pixels, the first slice 32 x 32");
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace osteon::geometry
