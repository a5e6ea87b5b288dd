#include "mc_table.h"

#include <stdexcept>

namespace osteon::geometry::detail {

namespace {

// The table is made by the compiler: generated at run time it cost a fresh process 0.17 ms
// at its first extraction, a tenth of a 64^3 one. Integer arithmetic on doubled coordinates
// (edge midpoints are halves), so the orientation tests are exact, as they were in doubles.
struct Vec {
  int x, y, z;
};
constexpr Vec operator-(Vec a, Vec b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
constexpr Vec cross(Vec a, Vec b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr int dot(Vec a, Vec b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

constexpr Vec doubledCorner(int c) {
  return {2 * (c & 1), 2 * ((c >> 1) & 1), 2 * ((c >> 2) & 1)};
}

constexpr std::array<std::uint8_t, 2> cornersOf(int edge) {
  const int axis = edge / 4;
  const int k = edge % 4;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  const int c0 = ((k & 1) << u) | (((k >> 1) & 1) << v);
  return {std::uint8_t(c0), std::uint8_t(c0 | (1 << axis))};
}

constexpr int edgeBetween(int a, int b) {
  const int diff = a ^ b;
  const int axis = diff == 1 ? 0 : (diff == 2 ? 1 : 2);
  const int base = a & b;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  return 4 * axis + ((base >> u) & 1) + 2 * ((base >> v) & 1);
}

constexpr Vec doubledMidpoint(int edge) {
  const auto c = cornersOf(edge);
  const Vec a = doubledCorner(c[0]), b = doubledCorner(c[1]);
  return {(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
}

// A table error stops the compilation (a throw is not a constant expression).
constexpr McCase buildCase(int config) {
  const auto inside = [config](int c) { return ((config >> c) & 1) != 0; };
  std::array<int, 12> next{};  // directed segment from edge -> edge
  for (int& n : next) n = -1;
  const auto addSegment = [&](int p, int q, const Vec& faceNormal, const Vec& ref, bool refInside) {
    // Orient p -> q so that (q - p) x n points to the inside part of the face.
    const Vec a = doubledMidpoint(p);
    const Vec b = doubledMidpoint(q);
    const int side = dot(cross(b - a, faceNormal), ref - a);
    if ((side > 0) != refInside) {
      const int t = p;
      p = q;
      q = t;
    }
    if (next[std::size_t(p)] != -1) throw std::logic_error("mc table: an edge leaves twice");
    next[std::size_t(p)] = q;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int sideBit = 0; sideBit < 2; ++sideBit) {
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      const int sign = sideBit ? 1 : -1;
      const Vec normal = {axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0};
      // The face's corners in cyclic order.
      const int base = sideBit << axis;
      const int corners[4] = {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
      int crossing[4] = {0, 0, 0, 0};
      int n = 0;
      for (int i = 0; i < 4; ++i) {
        if (inside(corners[i]) != inside(corners[(i + 1) % 4])) {
          crossing[n++] = edgeBetween(corners[i], corners[(i + 1) % 4]);
        }
      }
      if (n == 2) {
        int ref = 0;
        while (!inside(corners[ref])) ++ref;
        addSegment(crossing[0], crossing[1], normal, doubledCorner(corners[ref]), true);
      } else if (n == 4) {
        // Ambiguous face: cut off each outside corner, keeping the inside diagonal joined.
        for (int i = 0; i < 4; ++i) {
          if (inside(corners[i])) continue;
          const int e0 = edgeBetween(corners[(i + 3) % 4], corners[i]);
          const int e1 = edgeBetween(corners[i], corners[(i + 1) % 4]);
          addSegment(e0, e1, normal, doubledCorner(corners[i]), false);
        }
      }
    }
  }
  McCase out;
  std::array<bool, 12> used{};
  int count = 0;
  for (int start = 0; start < 12; ++start) {
    if (next[std::size_t(start)] == -1 || used[std::size_t(start)]) continue;
    if (out.loopCount == 4) throw std::logic_error("mc table: more than 4 loops");
    out.loopBegin[out.loopCount++] = std::uint8_t(count);
    for (int e = start; !used[std::size_t(e)]; e = next[std::size_t(e)]) {
      if (e == -1) throw std::logic_error("mc table: an open loop");
      used[std::size_t(e)] = true;
      out.edges[std::size_t(count++)] = std::uint8_t(e);
    }
  }
  out.loopBegin[out.loopCount] = std::uint8_t(count);
  return out;
}

constexpr std::array<McCase, 256> kTable = [] {
  std::array<McCase, 256> t{};
  for (int config = 0; config < 256; ++config) t[std::size_t(config)] = buildCase(config);
  return t;
}();

}  // namespace

std::array<std::uint8_t, 2> edgeCorners(int edge) {
  return cornersOf(edge);
}

const std::array<McCase, 256>& mcTable() {
  return kTable;
}

}  // namespace osteon::geometry::detail
