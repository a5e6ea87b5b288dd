#include "metrics.h"

#include <algorithm>
#include <cstring>

namespace osteon::viewer {

bool isRedPixel(const std::uint8_t* p) {
  return p[0] >= 128 && p[1] < 64 && p[2] < 64;
}
bool isWhitePixel(const std::uint8_t* p) {
  return p[0] >= 192 && p[1] >= 192 && p[2] >= 192;
}
bool isBackgroundPixel(const std::uint8_t* p) {
  return p[0] < 16 && p[1] < 16 && p[2] < 16;
}

PixelCounts countCrackPixels(const std::uint8_t* rgba, int width, int height) {
  PixelCounts c;
  const auto at = [&](int x, int y) {
    return rgba + 4 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
  };
  double sumX = 0.0, sumY = 0.0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::uint8_t* p = at(x, y);
      const int r = p[0], g = p[1], b = p[2];
      if (b > 120 && b > r + 60 && b > g + 30) ++c.levelMinus2;
      if (g > 100 && g > r + 50 && g > b + 40) ++c.levelMinus1;
      if (!isBackgroundPixel(p)) {
        sumX += x;
        sumY += height - 1 - y;
      }
      if (isBackgroundPixel(p)) {
        ++c.background;
      } else if (isWhitePixel(p)) {
        ++c.white;
      } else if (isRedPixel(p)) {
        ++c.red;
        bool silhouette = false;
        for (int dy = -1; dy <= 1 && !silhouette; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            // Outside the image counts as background: the frame's edge cuts the silhouette.
            if (nx < 0 || ny < 0 || nx >= width || ny >= height || isBackgroundPixel(at(nx, ny))) {
              silhouette = true;
              break;
            }
          }
        }
        if (silhouette) ++c.redSilhouette;
      } else {
        ++c.other;
      }
    }
  }
  const double n = double(c.foreground());
  if (n > 0.0) {
    c.centroidX = sumX / n / double(width);
    c.centroidY = sumY / n / double(height);
  }
  return c;
}

void flipRows(std::vector<std::uint8_t>& pixels, int width, int height, int channels) {
  const std::size_t row = std::size_t(width) * std::size_t(channels);
  std::vector<std::uint8_t> tmp(row);
  for (int y = 0; y < height / 2; ++y) {
    std::uint8_t* a = pixels.data() + std::size_t(y) * row;
    std::uint8_t* b = pixels.data() + std::size_t(height - 1 - y) * row;
    std::memcpy(tmp.data(), a, row);
    std::memcpy(a, b, row);
    std::memcpy(b, tmp.data(), row);
  }
}

void TimeSeries::add(double tS, float value) {
  times_.push_back(tS);
  values_.push_back(value);
  std::size_t drop = 0;
  while (drop < times_.size() && times_[drop] < tS - windowS_) ++drop;
  if (drop > 0) {
    times_.erase(times_.begin(), times_.begin() + std::ptrdiff_t(drop));
    values_.erase(values_.begin(), values_.begin() + std::ptrdiff_t(drop));
  }
}

float TimeSeries::max() const {
  return values_.empty() ? 0.0f : *std::max_element(values_.begin(), values_.end());
}

void FrameSeries::add(double ms) {
  all_.push_back(ms);
}

double FrameSeries::recentP99() const {
  if (all_.empty()) return 0.0;
  const std::size_t n = std::min(all_.size(), kRecent);
  std::vector<double> recent(all_.end() - std::ptrdiff_t(n), all_.end());
  return simulation::percentilesOf(std::move(recent)).p99;
}

}  // namespace osteon::viewer
