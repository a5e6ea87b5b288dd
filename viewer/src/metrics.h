// The numbers the viewer shows and reports, free of GL: the seed's pixel crack metric on a
// read-back frame, frame-time series, the |F| history for the plot.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "osteon/simulation/runner.h"

namespace osteon::viewer {

// The crack view draws front faces white and back faces red, unlit, on black. A red pixel with
// a background pixel among its 8 neighbours is on the silhouette, where rasterisation alone can
// show a back face; every other red pixel is a crack (the surface lets the inside through).
struct PixelCounts {
  std::uint64_t red = 0, white = 0, background = 0, other = 0;
  std::uint64_t redSilhouette = 0;
  std::uint64_t cracks() const { return red - redSilhouette; }
  // Pixels that are not background, and their centroid as a fraction of the image (x from
  // the left, y from the top): where the bone sits in the frame.
  std::uint64_t foreground() const { return red + white + other; }
  double centroidX = 0.0, centroidY = 0.0;
  // The level view's colours by hue (lit, so not exact values): level -1 green, level -2 blue.
  std::uint64_t levelMinus1 = 0, levelMinus2 = 0;
};

bool isRedPixel(const std::uint8_t* rgba);
bool isWhitePixel(const std::uint8_t* rgba);
bool isBackgroundPixel(const std::uint8_t* rgba);

// rgba: height rows of width RGBA8 pixels, bottom row first as GL reads them.
PixelCounts countCrackPixels(const std::uint8_t* rgba, int width, int height);

// Flips rows in place (GL reads bottom row first, images are top row first).
void flipRows(std::vector<std::uint8_t>& pixels, int width, int height, int channels);

// A window of the latest values in time order, for ImGui::PlotLines: samples older than
// `windowS` before the newest are dropped.
class TimeSeries {
 public:
  explicit TimeSeries(double windowS = 5.0) : windowS_(windowS) {}
  void add(double tS, float value);
  void clear() { times_.clear(), values_.clear(); }
  const std::vector<float>& values() const { return values_; }
  float max() const;

 private:
  double windowS_;
  std::vector<double> times_;
  std::vector<float> values_;
};

// Per-frame durations (ms) for the report's percentiles, and a short recent window for the
// status line.
class FrameSeries {
 public:
  void add(double ms);
  simulation::Percentiles percentiles() const { return simulation::percentilesOf(all_); }
  // The p99 of the last `recent` values.
  double recentP99() const;
  std::size_t size() const { return all_.size(); }

 private:
  std::vector<double> all_;
  static constexpr std::size_t kRecent = 256;
};

}  // namespace osteon::viewer
