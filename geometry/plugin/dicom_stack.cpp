// How a series' slices stack (dicom_series.h): sorted along the slice normal, the spacing
// between slices taken from their positions (never SliceThickness, which may overlap or leave
// gaps), a tilted gantry's shear kept in the third axis' step.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "dicom_series.h"

namespace osteon::dicom {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string name(const Slice& s) {
  return std::filesystem::path(s.file).filename().string();
}

double dot(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void checkAlike(const Series& series) {
  const Slice& first = series.slices.front();
  for (const Slice& s : series.slices) {
    if (!s.placed) {
      fail(name(s) +
           ": no ImagePositionPatient, ImageOrientationPatient or PixelSpacing (a slice needs "
           "them to be placed)");
    }
    for (int i = 0; i < 6; ++i) {
      if (std::abs(s.orientation[i] - first.orientation[i]) > 1e-4) {
        fail("slices " + name(first) + " and " + name(s) +
             " differ in ImageOrientationPatient (mixed orientations: not one stack)");
      }
    }
    for (int i = 0; i < 2; ++i) {
      if (std::abs(s.pixelSpacing[i] - first.pixelSpacing[i]) > 1e-6 * first.pixelSpacing[i]) {
        fail("slices " + name(first) + " and " + name(s) + " differ in PixelSpacing");
      }
    }
  }
  if (!(first.pixelSpacing[0] > 0.0 && first.pixelSpacing[1] > 0.0))
    fail(name(first) + ": PixelSpacing " + number(first.pixelSpacing[0]) + "\\" +
         number(first.pixelSpacing[1]) + " is not positive");
}

}  // namespace

Stack stackSlices(const Series& series) {
  if (series.slices.size() < 2) {
    fail("series " + series.uid + " has one slice (" + name(series.slices.front()) +
         "): a volume needs two or more");
  }
  checkAlike(series);
  const double* o = series.slices.front().orientation;
  const double row[3] = {o[0], o[1], o[2]}, col[3] = {o[3], o[4], o[5]};
  double normal[3] = {row[1] * col[2] - row[2] * col[1], row[2] * col[0] - row[0] * col[2],
                      row[0] * col[1] - row[1] * col[0]};
  const double length = std::sqrt(dot(normal, normal));
  if (!(length > 0.5)) fail("ImageOrientationPatient's row and column directions are parallel");
  for (double& c : normal) c /= length;
  Stack stack;
  stack.slices = series.slices;
  std::stable_sort(stack.slices.begin(), stack.slices.end(), [&](const Slice& a, const Slice& b) {
    return dot(a.position, normal) < dot(b.position, normal);
  });
  const std::size_t n = stack.slices.size();
  std::vector<double> gaps(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k)
    gaps[k] = dot(stack.slices[k + 1].position, normal) - dot(stack.slices[k].position, normal);
  std::vector<double> sorted = gaps;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2),
                   sorted.end());
  const double spacing = sorted[sorted.size() / 2];
  // Positions are written to about 0.01 mm; 2 % of the spacing tells a gap from rounding.
  const double tolerance = std::max(0.02 * spacing, 0.005);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const Slice &a = stack.slices[k], &b = stack.slices[k + 1];
    if (gaps[k] < tolerance) {
      fail("slices " + name(a) + " and " + name(b) + " lie at the same position " +
           number(dot(a.position, normal)) + " mm along the slice normal (two acquisitions?)");
    }
    if (std::abs(gaps[k] - spacing) > tolerance) {
      const double ratio = gaps[k] / spacing;
      const long missing = std::lround(ratio) - 1;
      const bool whole = std::abs(ratio - std::round(ratio)) * spacing <= tolerance && missing > 0;
      fail("a gap of " + number(gaps[k]) + " mm between slices " + name(a) + " and " + name(b) +
           " (at " + number(dot(a.position, normal)) + " and " + number(dot(b.position, normal)) +
           " mm along the slice normal) where the others are " + number(spacing) + " mm apart" +
           (whole ? ": " + std::to_string(missing) + (missing == 1 ? " slice" : " slices") +
                        " missing"
                  : ": unevenly spaced slices"));
    }
  }
  // The step from slice to slice, as the first and last slices give it; a tilted gantry shears
  // it off the normal. Every slice must lie on that line.
  const double* p0 = stack.slices.front().position;
  const double* pn = stack.slices.back().position;
  double step[3];
  for (int r = 0; r < 3; ++r) step[r] = (pn[r] - p0[r]) / double(n - 1);
  for (std::size_t k = 0; k < n; ++k) {
    const double* p = stack.slices[k].position;
    double off = 0.0;
    for (int r = 0; r < 3; ++r) off += std::pow(p[r] - (p0[r] + double(k) * step[r]), 2);
    if (std::sqrt(off) > tolerance) {
      fail("slice " + name(stack.slices[k]) + " lies " + number(std::sqrt(off)) +
           " mm off the line of the other slices' positions (not one stack)");
    }
  }
  const double* ps = stack.slices.front().pixelSpacing;  // between rows, between columns
  for (int r = 0; r < 3; ++r) {
    stack.m[r][0] = row[r] * ps[1];
    stack.m[r][1] = col[r] * ps[0];
    stack.m[r][2] = step[r];
    stack.centre0[r] = p0[r];
  }
  return stack;
}

}  // namespace osteon::dicom
