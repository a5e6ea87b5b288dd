// The DICOM plugin's series logic (dicom_series.cpp): which files of a folder are slices of
// which series, and how one series' slices stack into a volume. GDCM's Scanner reads only the
// headers, up to the tags below, so a folder of a thousand slices is sorted without decoding one.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace osteon::dicom {

// A refusal inside the plugin; the C interface turns it into its return code and errbuf.
struct Failure {
  int code = 2;
  std::string reason;
};
[[noreturn]] inline void fail(const std::string& reason) {
  throw Failure{2, reason};
}

struct Slice {
  std::string file;
  double position[3] = {0, 0, 0};  // ImagePositionPatient: LPS mm of the first pixel's centre
  double orientation[6] = {0, 0, 0, 0, 0, 0};  // ImageOrientationPatient: row, column directions
  double pixelSpacing[2] = {0, 0};             // PixelSpacing: between rows, between columns (mm)
  double slope = 1.0, intercept = 0.0;
  int frames = 1;
  bool placed = false;  // the three above were found (a slice without them cannot be stacked)
};

struct Series {
  std::string uid, description, sopClass;
  std::vector<Slice> slices;
};

// Every element's declared length checked against the file (dicom_walk.cpp), given the file's
// transfer syntax UID: GDCM would allocate what a header declares before finding the file short.
void refuseLyingLengths(const std::string& file, const std::string& transferSyntax);
// One of DICOM's two-letter value representations ("US", "OB", ...).
bool isVr(const std::string& vr);

// The series of a folder (its regular files, not its sub-folders), or of one file: a multi-frame
// file alone, a one-frame file with the slices of its series beside it. Files that are not DICOM
// are passed over; a folder with no DICOM slice is refused.
// `tick` is called after each file's header is checked (a heartbeat for the caller).
std::vector<Series> scanSeries(const std::string& path, const std::function<void()>& tick);

// `uid`, or ("" given) the series with most slices; a tie, or a UID not there, is refused with
// the list of the series.
const Series& pickSeries(const std::vector<Series>& all, const std::string& uid);

// A series' slices in order along the slice normal, with the volume's geometry: m's columns
// the step along rows, columns and slices (LPS mm), centre0 the first voxel's centre. Refuses
// mixed orientations or spacings, a lone slice, two slices at one position, a gap (a missing
// slice) or uneven spacing, and positions off the line of the stack.
struct Stack {
  std::vector<Slice> slices;
  double m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  double centre0[3] = {0, 0, 0};
};
Stack stackSlices(const Series& series);

// "UID (N slices, description)" for each, comma-separated.
std::string describeSeries(const std::vector<Series>& all);

}  // namespace osteon::dicom
