// A 16-bit mono WAV read back and its spectrum probed at chosen frequencies (Goertzel), for the
// tests of the drill's sound.
#pragma once

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace osteon::test {

struct WavSamples {
  std::uint32_t rateHz = 0;
  std::vector<double> samples;  // in [-1, 1]
};

// The samples of a mono 16-bit PCM WAV with osteon's 44-byte header; empty when it is not one.
inline WavSamples readWav(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
  WavSamples w;
  const auto u32 = [&b](std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
  };
  if (b.size() < 44 || std::string(b.begin(), b.begin() + 4) != "RIFF" ||
      std::string(b.begin() + 36, b.begin() + 40) != "data" || b[22] != 1 || b[34] != 16) {
    return w;
  }
  w.rateHz = u32(24);
  const std::size_t n = u32(40) / 2;
  if (44 + 2 * n > b.size()) return w;
  w.samples.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto v =
        static_cast<std::int16_t>(std::uint16_t(b[44 + 2 * i]) | std::uint16_t(b[45 + 2 * i]) << 8);
    w.samples[i] = v / 32767.0;
  }
  return w;
}

// The amplitude of the frequency hz in samples [begin, end) (Goertzel, Hann window): a sine of
// amplitude A on a bin gives about A / 2.
inline double amplitudeAt(const std::vector<double>& x, std::size_t begin, std::size_t end,
                          double hz, double rateHz) {
  const double w = 2.0 * M_PI * hz / rateHz;
  const double coeff = 2.0 * std::cos(w);
  double s1 = 0.0, s2 = 0.0;
  const double n = double(end - begin);
  for (std::size_t i = begin; i < end; ++i) {
    const double hann = 0.5 - 0.5 * std::cos(2.0 * M_PI * double(i - begin) / n);
    const double s = x[i] * hann + coeff * s1 - s2;
    s2 = s1;
    s1 = s;
  }
  const double power = s1 * s1 + s2 * s2 - coeff * s1 * s2;
  return std::sqrt(std::max(0.0, power)) / n;
}

// The mean amplitude over [loHz, hiHz] in `steps` probes: a band's level.
inline double bandLevel(const std::vector<double>& x, std::size_t begin, std::size_t end,
                        double loHz, double hiHz, double rateHz, int steps = 40) {
  double sum = 0.0;
  for (int i = 0; i < steps; ++i) {
    sum += amplitudeAt(x, begin, end, loHz + (hiHz - loHz) * (i + 0.5) / steps, rateHz);
  }
  return sum / steps;
}

}  // namespace osteon::test
