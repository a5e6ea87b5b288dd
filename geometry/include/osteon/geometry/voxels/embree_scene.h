// An Embree 3 scene over a triangle mesh, owned RAII-style (style rule 7: C handles live in
// unique_ptr with custom deleters). Used by the voxelizer (ray projection, seed 3.2), the
// density rule (distance to the surface) and validation (pixel crack metric, collision
// cross-check).
#pragma once

#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include <embree3/rtcore.h>

#include "osteon/geometry/io/mesh.h"

namespace osteon::geometry {

struct EmbreeDeviceDeleter {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct EmbreeSceneDeleter {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
using EmbreeDevicePtr = std::unique_ptr<std::remove_pointer_t<RTCDevice>, EmbreeDeviceDeleter>;
using EmbreeScenePtr = std::unique_ptr<std::remove_pointer_t<RTCScene>, EmbreeSceneDeleter>;

class EmbreeScene {
 public:
  // Builds a robust-flagged BVH over the mesh (single precision, as Embree works) with
  // context filter functions enabled, so callers can collect every hit along a ray.
  // Throws std::runtime_error when Embree cannot create a device.
  explicit EmbreeScene(const TriangleMesh& mesh);

  RTCScene handle() const { return scene_.get(); }
  // Embree holds the mesh as single-precision offsets from this point (the centre of its
  // bounds), so precision does not fade for meshes far from the origin. Rays and queries
  // given to handle() must use the same offsets.
  glm::dvec3 centreMm() const { return centreMm_; }
  const TriangleMesh& mesh() const { return *mesh_; }

  // Distance from pointMm to the nearest point of the mesh if it is within maxDistanceMm,
  // otherwise a negative value. closestMm receives that nearest point when found.
  double distanceWithin(const glm::dvec3& pointMm, double maxDistanceMm,
                        glm::dvec3* closestMm = nullptr) const;
  // Appends to `out` every triangle that may lie within radiusMm of pointMm (a superset: the
  // triangles whose bounding box does, found through the BVH; a triangle may repeat).
  void trianglesNear(const glm::dvec3& pointMm, double radiusMm,
                     std::vector<std::uint32_t>& out) const;
  // Whether the segment from fromMm to toMm meets the mesh: one occlusion ray, watertight (the
  // scene is robust), so a segment between the two sides of a closed mesh always hits.
  bool segmentHits(const glm::dvec3& fromMm, const glm::dvec3& toMm) const;

 private:
  const TriangleMesh* mesh_;
  glm::dvec3 centreMm_{0.0};
  EmbreeDevicePtr device_;
  EmbreeScenePtr scene_;
};

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::dvec3 closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                  const glm::dvec3& c);

}  // namespace osteon::geometry
