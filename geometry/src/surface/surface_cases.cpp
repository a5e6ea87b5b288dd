#include "surface_cases.h"

namespace osteon::geometry::detail {

namespace {

// What each case adds: triangles, loop-centre vertices, centre-loop entries, loop corners.
struct CaseCounts {
  std::array<std::uint8_t, 256> triangles, centres, loopEntries, corners;
};

const CaseCounts& caseCounts() {
  static const CaseCounts counts = [] {
    CaseCounts c{};
    for (int config = 0; config < 256; ++config) {
      const McCase& mc = mcTable()[std::size_t(config)];
      int tris = 0, centres = 0, entries = 0, corners = 0;
      for (int loop = 0; loop < mc.loopCount; ++loop) {
        const int k = mc.loopBegin[std::size_t(loop) + 1] - mc.loopBegin[std::size_t(loop)];
        tris += k == 3 ? 1 : (k == 4 ? 2 : k);
        centres += k >= 5 ? 1 : 0;
        entries += k >= 5 ? k : 0;
        corners += k;
      }
      c.triangles[std::size_t(config)] = std::uint8_t(tris);
      c.centres[std::size_t(config)] = std::uint8_t(centres);
      c.loopEntries[std::size_t(config)] = std::uint8_t(entries);
      c.corners[std::size_t(config)] = std::uint8_t(corners);
    }
    return c;
  }();
  return counts;
}

}  // namespace

const std::array<FlatCase, 256>& flatCases() {
  static const std::array<FlatCase, 256> cases = [] {
    std::array<FlatCase, 256> t{};
    for (int config = 0; config < 256; ++config) {
      const McCase& mc = mcTable()[std::size_t(config)];
      FlatCase& f = t[std::size_t(config)];
      f.loopCount = std::uint8_t(mc.loopCount);
      for (int loop = 0; loop < mc.loopCount; ++loop) {
        const int k = mc.loopBegin[std::size_t(loop) + 1] - mc.loopBegin[std::size_t(loop)];
        f.loopLength[std::size_t(loop)] = std::uint8_t(k);
        f.triangleCount = std::uint8_t(f.triangleCount + (k == 3 ? 1 : (k == 4 ? 2 : k)));
        f.longLoops = std::uint8_t(f.longLoops + (k >= 5 ? 1 : 0));
      }
      const auto slot = [&](int i) { return kEdgeSlot[mc.edges[std::size_t(i)]]; };
      std::size_t n = 0;
      for (int loop = 0; loop < mc.loopCount; ++loop) {
        const int first = mc.loopBegin[std::size_t(loop)];
        const int k = mc.loopBegin[std::size_t(loop) + 1] - first;
        if (f.longLoops != 0) {
          for (int i = 0; i < k; ++i) f.slots.at(n++) = slot(first + i);
        } else {
          for (int i = 1; i + 1 < k; ++i) {
            f.slots.at(n++) = slot(first);
            f.slots.at(n++) = slot(first + i);
            f.slots.at(n++) = slot(first + i + 1);
          }
        }
      }
      // Unused triangle slots repeat the first triangle: pass 3 writes two triangles whatever
      // the count, and their ids must be ones the case's cell has made.
      if (f.longLoops == 0 && n > 0) {
        for (std::size_t i = n; i < f.slots.size(); ++i) f.slots[i] = f.slots[i % 3];
      }
    }
    return t;
  }();
  return cases;
}

const std::array<std::uint64_t, 256>& packedCaseCounts() {
  static const std::array<std::uint64_t, 256> packed = [] {
    const CaseCounts& c = caseCounts();
    std::array<std::uint64_t, 256> p{};
    for (std::size_t i = 0; i < 256; ++i) {
      p[i] = std::uint64_t(c.triangles[i]) | (std::uint64_t(c.centres[i]) << 16) |
             (std::uint64_t(c.loopEntries[i]) << 32) | (std::uint64_t(c.corners[i]) << 48);
    }
    return p;
  }();
  return packed;
}

}  // namespace osteon::geometry::detail
