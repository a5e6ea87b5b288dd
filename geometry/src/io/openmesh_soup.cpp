#include "openmesh_soup.h"

#include <glm/geometric.hpp>

namespace osteon::geometry::detail {

VertexHandle SoupImporter::addPoint(double x, double y, double z) {
  if (mesh_.positionsMm.size() >= maxVertices_) {
    fail("more vertices than the file's size allows (corrupt counts?)");
    return VertexHandle();
  }
  mesh_.positionsMm.emplace_back(x, y, z);
  return VertexHandle(static_cast<int>(mesh_.positionsMm.size() - 1));
}

void SoupImporter::set_point(VertexHandle vh, const Vec3f& p) {
  if (vh.is_valid() && static_cast<std::size_t>(vh.idx()) < mesh_.positionsMm.size()) {
    mesh_.positionsMm[static_cast<std::size_t>(vh.idx())] = glm::dvec3(p[0], p[1], p[2]);
  }
}

FaceHandle SoupImporter::add_face(const VHandles& corners) {
  const std::size_t face = polygonsRead_++;
  if (error_) return FaceHandle();
  const std::size_t vertexCount = mesh_.positionsMm.size();
  for (const VertexHandle& vh : corners) {
    if (!vh.is_valid() || static_cast<std::size_t>(vh.idx()) >= vertexCount) {
      fail("face " + std::to_string(face) + " references vertex " + std::to_string(vh.idx()) +
           ", out of range (the file has " + std::to_string(vertexCount) + " vertices)");
      return FaceHandle();
    }
  }
  if (corners.size() < 3) {
    ++degenerateDropped_;
    return FaceHandle();
  }
  if (corners.size() > 3) ++polygonsTriangulated_;
  // Fan from the first corner: exact for the convex polygons mesh exporters write.
  bool emitted = false;
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    const glm::u32vec3 tri(static_cast<std::uint32_t>(corners[0].idx()),
                           static_cast<std::uint32_t>(corners[k].idx()),
                           static_cast<std::uint32_t>(corners[k + 1].idx()));
    if (tri.x == tri.y || tri.y == tri.z || tri.x == tri.z) continue;
    mesh_.triangles.push_back(tri);
    emitted = true;
  }
  if (!emitted) ++degenerateDropped_;
  return emitted ? FaceHandle(static_cast<int>(face)) : FaceHandle();
}

Vec3d SoupExporter::pointd(VertexHandle vh) const {
  const glm::dvec3& p = mesh_.positionsMm[static_cast<std::size_t>(vh.idx())];
  return Vec3d(p.x, p.y, p.z);
}

unsigned int SoupExporter::get_vhandles(FaceHandle fh, std::vector<VertexHandle>& corners) const {
  const glm::u32vec3& t = mesh_.triangles[static_cast<std::size_t>(fh.idx())];
  corners.clear();
  for (int c = 0; c < 3; ++c) corners.emplace_back(static_cast<int>(t[c]));
  return 3;
}

Vec3d SoupExporter::normald(FaceHandle fh) const {
  const glm::u32vec3& t = mesh_.triangles[static_cast<std::size_t>(fh.idx())];
  const glm::dvec3& a = mesh_.positionsMm[t.x];
  const glm::dvec3 n = glm::cross(mesh_.positionsMm[t.y] - a, mesh_.positionsMm[t.z] - a);
  const double len = glm::length(n);
  const glm::dvec3 unit = len > 0.0 ? n / len : glm::dvec3(0.0);
  return Vec3d(unit.x, unit.y, unit.z);
}

}  // namespace osteon::geometry::detail
