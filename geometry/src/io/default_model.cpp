#include <cstddef>

#include "osteon/geometry/io/humerus_model.h"

namespace osteon::geometry {

namespace detail {
// In default_model_data.cpp, written at build time by tools/embed_default_model.cpp.
extern const double kDefaultPositionsMm[];
extern const unsigned kDefaultTriangles[];
extern const std::size_t kDefaultVertexCount, kDefaultTriangleCount;
extern const double kDefaultFrame[10];  // head centre, head radius, head axis, shaft axis
}  // namespace detail

const HumerusModel& defaultHumerusModel() {
  static const HumerusModel model = [] {
    HumerusModel m;
    m.mesh.positionsMm.resize(detail::kDefaultVertexCount);
    for (std::size_t i = 0; i < detail::kDefaultVertexCount; ++i) {
      const double* p = detail::kDefaultPositionsMm + 3 * i;
      m.mesh.positionsMm[i] = {p[0], p[1], p[2]};
    }
    m.mesh.triangles.resize(detail::kDefaultTriangleCount);
    for (std::size_t i = 0; i < detail::kDefaultTriangleCount; ++i) {
      const unsigned* t = detail::kDefaultTriangles + 3 * i;
      m.mesh.triangles[i] = {t[0], t[1], t[2]};
    }
    const double* f = detail::kDefaultFrame;
    m.headCentreMm = {f[0], f[1], f[2]};
    m.headRadiusMm = f[3];
    m.headAxis = {f[4], f[5], f[6]};
    m.shaftAxis = {f[7], f[8], f[9]};
    return m;
  }();
  return model;
}

}  // namespace osteon::geometry
