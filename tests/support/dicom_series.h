// Small DICOM CT series written with GDCM itself (gdcm::ImageWriter; compressed through
// gdcm::ImageChangeTransferSyntax), for tests that read them back through osteon's loader.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "support/volume_files.h"

namespace osteon::test {

struct DicomSlice {
  int columns = 4, rows = 3;
  std::vector<std::int32_t> stored;  // columns x rows stored values, row after row
  double position[3] = {0, 0, 0};    // ImagePositionPatient, LPS mm
  double orientation[6] = {1, 0, 0, 0, 1, 0};
  double pixelSpacing[2] = {1, 1};  // between rows, between columns
  double slope = 1.0, intercept = 0.0;
  bool isSigned = true;   // int16, else uint16
  bool eightBit = false;  // uint8 (for JPEG baseline)
  std::string seriesUid = "1.2.826.0.1.3680043.2.1125.1";
  std::string sopClass = "1.2.840.10008.5.1.4.1.1.2";  // CT image storage
  std::string transferSyntax;  // "": explicit VR little endian; else "jpegls", "jpeg2000",
                               // "jpeglossless", "jpegbaseline", "rle"
};

// Writes one slice to `path`; throws std::runtime_error when GDCM cannot.
void writeDicomSlice(const std::string& path, const DicomSlice& slice);

// One multi-frame file of `frames` slices of `slice`'s size and geometry, `sliceSpacingMm` apart
// along the normal, as GDCM writes a 3-D image (an enhanced CT: per-frame functional groups).
void writeDicomMultiFrame(const std::string& path, const DicomSlice& slice, int frames,
                          double sliceSpacingMm);

// A stack of `count` slices along z, `spacingMm` apart from z = z0, slice k holding values
// 100 * k + (x + columns * y) - 1024 (stored).
std::vector<DicomSlice> dicomStack(int count, double z0, double spacingMm, int columns = 4,
                                   int rows = 3);

// `hu` on `v`'s geometry as a CT series in `folder` (created): a plain int16 slice per z, S<k>.dcm.
void writeDicomVolume(const std::string& folder, const TestVolume& v,
                      const std::vector<double>& hu);

}  // namespace osteon::test
