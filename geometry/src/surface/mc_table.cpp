#include "mc_table.h"

#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace osteon::geometry::detail {

namespace {

glm::dvec3 cornerPosition(int c) {
  return glm::dvec3(c & 1, (c >> 1) & 1, (c >> 2) & 1);
}

int edgeBetween(int a, int b) {
  const int diff = a ^ b;
  const int axis = diff == 1 ? 0 : (diff == 2 ? 1 : 2);
  const int base = a & b;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  return 4 * axis + ((base >> u) & 1) + 2 * ((base >> v) & 1);
}

glm::dvec3 edgeMidpoint(int edge) {
  const auto c = edgeCorners(edge);
  return 0.5 * (cornerPosition(c[0]) + cornerPosition(c[1]));
}

McCase buildCase(int config) {
  const auto inside = [config](int c) { return ((config >> c) & 1) != 0; };
  std::array<int, 12> next;  // directed segment from edge -> edge
  next.fill(-1);
  const auto addSegment = [&](int p, int q, const glm::dvec3& faceNormal, const glm::dvec3& ref,
                              bool refInside) {
    // Orient p -> q so that (q - p) x n points to the inside part of the face.
    const glm::dvec3 a = edgeMidpoint(p);
    const glm::dvec3 b = edgeMidpoint(q);
    const double side = glm::dot(glm::cross(b - a, faceNormal), ref - a);
    if ((side > 0.0) != refInside) std::swap(p, q);
    if (next[std::size_t(p)] != -1) {
      throw std::logic_error("mc table: edge " + std::to_string(p) + " leaves twice in case " +
                             std::to_string(config));
    }
    next[std::size_t(p)] = q;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (int sideBit = 0; sideBit < 2; ++sideBit) {
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      glm::dvec3 normal(0.0);
      normal[axis] = sideBit ? 1.0 : -1.0;
      // The face's corners in cyclic order.
      const int base = sideBit << axis;
      const int corners[4] = {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
      int crossing[4];
      int n = 0;
      for (int i = 0; i < 4; ++i) {
        if (inside(corners[i]) != inside(corners[(i + 1) % 4])) {
          crossing[n++] = edgeBetween(corners[i], corners[(i + 1) % 4]);
        }
      }
      if (n == 2) {
        int ref = 0;
        while (!inside(corners[ref])) ++ref;
        addSegment(crossing[0], crossing[1], normal, cornerPosition(corners[ref]), true);
      } else if (n == 4) {
        // Ambiguous face: cut off each outside corner, keeping the inside diagonal joined.
        for (int i = 0; i < 4; ++i) {
          if (inside(corners[i])) continue;
          const int e0 = edgeBetween(corners[(i + 3) % 4], corners[i]);
          const int e1 = edgeBetween(corners[i], corners[(i + 1) % 4]);
          addSegment(e0, e1, normal, cornerPosition(corners[i]), false);
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
      if (e == -1) throw std::logic_error("mc table: open loop in case " + std::to_string(config));
      used[std::size_t(e)] = true;
      out.edges[std::size_t(count++)] = std::uint8_t(e);
    }
  }
  out.loopBegin[out.loopCount] = std::uint8_t(count);
  return out;
}

}  // namespace

std::array<std::uint8_t, 2> edgeCorners(int edge) {
  const int axis = edge / 4;
  const int k = edge % 4;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  const int c0 = ((k & 1) << u) | (((k >> 1) & 1) << v);
  return {std::uint8_t(c0), std::uint8_t(c0 | (1 << axis))};
}

const std::array<McCase, 256>& mcTable() {
  static const std::array<McCase, 256> table = [] {
    std::array<McCase, 256> t;
    for (int config = 0; config < 256; ++config) t[std::size_t(config)] = buildCase(config);
    return t;
  }();
  return table;
}

}  // namespace osteon::geometry::detail
