#include "support/shapes.h"

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace osteon::test {

using geometry::TriangleMesh;

TriangleMesh makeSphere(double radiusMm, int slices, int stacks, glm::dvec3 centreMm) {
  TriangleMesh m;
  const double pi = 3.14159265358979323846;
  m.positionsMm.push_back(centreMm + glm::dvec3(0, 0, radiusMm));  // north pole
  for (int i = 1; i < stacks; ++i) {
    const double theta = pi * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * pi * j / slices;
      m.positionsMm.push_back(centreMm + radiusMm * glm::dvec3(std::sin(theta) * std::cos(phi),
                                                               std::sin(theta) * std::sin(phi),
                                                               std::cos(theta)));
    }
  }
  m.positionsMm.push_back(centreMm + glm::dvec3(0, 0, -radiusMm));  // south pole
  const auto ring = [&](int i, int j) {
    return std::uint32_t(1 + (i - 1) * slices + ((j % slices) + slices) % slices);
  };
  const std::uint32_t south = std::uint32_t(m.positionsMm.size() - 1);
  for (int j = 0; j < slices; ++j) m.triangles.push_back({0u, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  for (int j = 0; j < slices; ++j) {
    m.triangles.push_back({south, ring(stacks - 1, j + 1), ring(stacks - 1, j)});
  }
  return m;
}

TriangleMesh makeBox(glm::dvec3 lo, glm::dvec3 hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.positionsMm.push_back({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  }
  // Two outward CCW triangles per face.
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TriangleMesh makeTorus(double majorMm, double minorMm, int majorSegments, int minorSegments) {
  TriangleMesh m;
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < majorSegments; ++i) {
    const double u = 2.0 * pi * i / majorSegments;
    for (int j = 0; j < minorSegments; ++j) {
      const double v = 2.0 * pi * j / minorSegments;
      const double r = majorMm + minorMm * std::cos(v);
      m.positionsMm.push_back({r * std::cos(u), r * std::sin(u), minorMm * std::sin(v)});
    }
  }
  const auto at = [&](int i, int j) {
    return std::uint32_t((i % majorSegments) * minorSegments + (j % minorSegments));
  };
  for (int i = 0; i < majorSegments; ++i) {
    for (int j = 0; j < minorSegments; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

}  // namespace osteon::test
