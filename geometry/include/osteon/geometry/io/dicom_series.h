// The series a DICOM folder holds (for `osteon info`), read through the GDCM plugin without
// decoding a pixel.
#pragma once

#include <string>
#include <vector>

namespace osteon::geometry {

struct DicomSeries {
  std::string uid;  // Series Instance UID
  int slices = 0;   // files of the series
  std::string description;
};

// The series of a DICOM folder, or of the folder of a one-slice file (a multi-frame file alone),
// by UID. Throws InputError "<path>: <reason>".
std::vector<DicomSeries> listDicomSeries(const std::string& path);

// The series loadVolume reads without --series: the one with most slices; -1 for a tie (refused).
int defaultDicomSeries(const std::vector<DicomSeries>& all);

}  // namespace osteon::geometry
