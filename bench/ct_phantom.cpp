#include "ct_phantom.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <glm/glm.hpp>

namespace osteon::bench {

namespace {

constexpr int kNx = 512, kNy = 512, kNz = 350;

// HU at an LPS point (mm, the volume centred on the origin): two shafts along S at L -60 and
// +60 mm, outer radius 14 mm, 5 mm of cortex, each ending at S 60 mm in a head of radius 24 mm
// with a 3 mm shell; air elsewhere.
double boneHu(glm::dvec3 p) {
  double hu = -1000.0;
  for (const double cx : {-60.0, 60.0}) {
    const double r = std::hypot(p.x - cx, p.y);
    const double head = glm::length(p - glm::dvec3(cx, 0.0, 60.0));
    const double cortex = 1250.0 + 250.0 * std::sin(p.z / 25.0 + cx / 30.0);
    const double marrow = 475.0 + 75.0 * std::cos(p.z / 17.0);
    if (r < 14.0 && p.z < 60.0) hu = r > 9.0 ? cortex : marrow;
    if (head < 24.0) hu = head > 21.0 ? cortex : marrow;
  }
  return hu;
}

struct Layout {
  glm::dvec3 spacingMm;
  double tiltDeg;
};

// The stored axes' steps in LPS (columns): the spacing, tilted about the L axis (as a gantry).
glm::dmat3 indexToLps(const Layout& l) {
  const double a = l.tiltDeg * 3.14159265358979323846 / 180.0;
  const glm::dmat3 tilt(1.0, 0.0, 0.0, 0.0, std::cos(a), std::sin(a), 0.0, -std::sin(a),
                        std::cos(a));
  return tilt *
         glm::dmat3(l.spacingMm.x, 0.0, 0.0, 0.0, l.spacingMm.y, 0.0, 0.0, 0.0, l.spacingMm.z);
}

}  // namespace

bool writeCtPhantom(const std::string& kind, const std::string& path) {
  Layout layout{{0.7, 0.7, 1.0}, 0.0};
  const bool labels = kind == "labels";
  if (kind == "iso") {
    layout.spacingMm = glm::dvec3(0.7);
  } else if (kind == "thick") {
    layout.spacingMm = {0.98, 0.98, 2.0};
  } else if (kind == "oblique") {
    layout.tiltDeg = 15.0;
  } else if (kind != "aniso" && !labels) {
    return false;
  }
  const glm::dmat3 m = indexToLps(layout);
  const glm::dvec3 centre0 = -(m * (glm::dvec3(kNx, kNy, kNz) - 1.0) * 0.5);
  std::ofstream out(path, std::ios::binary);
  out << "NRRD0004\ntype: " << (labels ? "uint8" : "int16")
      << "\ndimension: 3\nspace: left-posterior-superior\nsizes: " << kNx << " " << kNy << " "
      << kNz << "\nspace directions:";
  out.precision(12);
  for (int a = 0; a < 3; ++a) out << " (" << m[a].x << "," << m[a].y << "," << m[a].z << ")";
  out << "\nkinds: domain domain domain\nendian: little\nencoding: raw\nspace origin: ("
      << centre0.x << "," << centre0.y << "," << centre0.z << ")\n\n";
  std::vector<std::int16_t> slice(std::size_t(kNx) * kNy);
  std::uint32_t seed = 1;
  for (int z = 0; z < kNz; ++z) {
    for (int y = 0; y < kNy; ++y) {
      for (int x = 0; x < kNx; ++x) {
        seed = seed * 1664525u + 1013904223u;
        const double noise = double(seed >> 24) / 255.0 * 40.0 - 20.0;
        const glm::dvec3 p = centre0 + m * glm::dvec3(x, y, z);
        slice[std::size_t(y) * kNx + std::size_t(x)] = std::int16_t(std::lround(boneHu(p) + noise));
      }
    }
    if (labels) {  // the bone's label map: 1 at or above 300 HU, else 0
      std::vector<std::uint8_t> bone(slice.size());
      for (std::size_t i = 0; i < slice.size(); ++i) bone[i] = slice[i] >= 300 ? 1 : 0;
      out.write(reinterpret_cast<const char*>(bone.data()), std::streamsize(bone.size()));
      continue;
    }
    out.write(reinterpret_cast<const char*>(slice.data()),
              std::streamsize(slice.size() * sizeof(std::int16_t)));
  }
  if (!out) throw std::runtime_error(path + ": cannot write the phantom");
  return true;
}

}  // namespace osteon::bench
