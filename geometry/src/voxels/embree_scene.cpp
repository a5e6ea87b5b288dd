#include "osteon/geometry/voxels/embree_scene.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace osteon::geometry {

EmbreeScene::EmbreeScene(const TriangleMesh& mesh) : mesh_(&mesh) {
  if (!mesh.triangles.empty()) {
    const Aabb box = bounds(mesh);
    centreMm_ = 0.5 * (box.minMm + box.maxMm);
  }
  device_.reset(rtcNewDevice(nullptr));
  if (!device_) {
    throw std::runtime_error("Embree: cannot create a device (error " +
                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  }
  scene_.reset(rtcNewScene(device_.get()));
  // ROBUST: no accuracy-reducing shortcuts, so rays through shared edges are not lost.
  rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);

  RTCGeometry geometry = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.positionsMm.size()));
  for (std::size_t v = 0; v < mesh.positionsMm.size(); ++v) {
    const glm::dvec3 local = mesh.positionsMm[v] - centreMm_;
    vertices[3 * v + 0] = float(local.x);
    vertices[3 * v + 1] = float(local.y);
    vertices[3 * v + 2] = float(local.z);
  }
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c) indices[3 * t + std::size_t(c)] = mesh.triangles[t][c];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_.get(), geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_.get());
  if (rtcGetDeviceError(device_.get()) != RTC_ERROR_NONE) {
    throw std::runtime_error("Embree: building the scene failed");
  }
}

glm::dvec3 closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                  const glm::dvec3& c) {
  // Voronoi regions of the vertices, then edges, then the face.
  const glm::dvec3 ab = b - a;
  const glm::dvec3 ac = c - a;
  const glm::dvec3 ap = p - a;
  const double d1 = glm::dot(ab, ap);
  const double d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp);
  const double d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp);
  const double d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

namespace {

struct ClosestQuery {
  const TriangleMesh* mesh;
  glm::dvec3 point;
  double bestDistance;
  glm::dvec3 bestPoint;
  bool found;
};

// Squared distance from p to the bounding box of triangle abc: a lower bound on the squared
// distance to the triangle itself.
inline double boxDistance2(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                           const glm::dvec3& c) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min(a[k], std::min(b[k], c[k]));
    const double hi = std::max(a[k], std::max(b[k], c[k]));
    const double e = std::max(0.0, std::max(lo - p[k], p[k] - hi));
    d2 += e * e;
  }
  return d2;
}

bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  const glm::u32vec3& t = q->mesh->triangles[args->primID];
  const glm::dvec3& a = q->mesh->positionsMm[t.x];
  const glm::dvec3& b = q->mesh->positionsMm[t.y];
  const glm::dvec3& cc = q->mesh->positionsMm[t.z];
  // Most triangles Embree offers lie beyond the best distance so far; their bounding box
  // says so cheaply. The margin (far above rounding) keeps every triangle that could still
  // win, so the answer is the same bits as without the test.
  const double reject = q->bestDistance * (1.0 + 1e-9) + 1e-12;
  if (boxDistance2(q->point, a, b, cc) > reject * reject) return false;
  const glm::dvec3 c = closestPointOnTriangle(q->point, a, b, cc);
  const double d = glm::length(c - q->point);
  if (d < q->bestDistance) {
    q->bestDistance = d;
    q->bestPoint = c;
    q->found = true;
    args->query->radius = float(d);  // shrink the search: Embree prunes farther nodes
    return true;
  }
  return false;
}

// Embree's point query around `localMm` (relative to the scene's centre, as its BVH is).
RTCPointQuery pointQueryAt(const glm::dvec3& localMm, float radiusMm) {
  RTCPointQuery query;
  query.x = float(localMm.x);
  query.y = float(localMm.y);
  query.z = float(localMm.z);
  query.time = 0.f;
  query.radius = radiusMm;
  return query;
}

}  // namespace

double EmbreeScene::distanceWithin(const glm::dvec3& pointMm, double maxDistanceMm,
                                   glm::dvec3* closestMm) const {
  ClosestQuery q{mesh_, pointMm, maxDistanceMm, glm::dvec3(0.0), false};
  RTCPointQuery query = pointQueryAt(pointMm - centreMm_, float(maxDistanceMm));
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_.get(), &query, &context, closestPointCallback, &q);
  if (!q.found) return -1.0;
  if (closestMm) *closestMm = q.bestPoint;
  return q.bestDistance;
}

namespace {

struct GatherQuery {
  const TriangleMesh* mesh;
  glm::dvec3 point;
  double radius2;
  std::vector<std::uint32_t>* out;
};

bool gatherCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<GatherQuery*>(args->userPtr);
  const glm::u32vec3& t = q->mesh->triangles[args->primID];
  if (boxDistance2(q->point, q->mesh->positionsMm[t.x], q->mesh->positionsMm[t.y],
                   q->mesh->positionsMm[t.z]) <= q->radius2) {
    q->out->push_back(args->primID);
  }
  return false;  // the radius stays: every triangle within it is wanted
}

}  // namespace

void EmbreeScene::trianglesNear(const glm::dvec3& pointMm, double radiusMm,
                                std::vector<std::uint32_t>& out) const {
  if (mesh_->triangles.empty()) return;
  const double padded = radiusMm * (1.0 + 1e-9) + 1e-9;  // over the box test's rounding
  GatherQuery q{mesh_, pointMm, padded * padded, &out};
  // Embree tests its boxes in single precision around a rounded point: a margin far above
  // that rounding keeps every box the exact sphere touches.
  RTCPointQuery query = pointQueryAt(pointMm - centreMm_, float(radiusMm * (1.0 + 1e-4) + 1e-3));
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_.get(), &query, &context, gatherCallback, &q);
}

bool EmbreeScene::segmentHits(const glm::dvec3& fromMm, const glm::dvec3& toMm) const {
  const glm::dvec3 d = toMm - fromMm;
  const double length = glm::length(d);
  if (!(length > 0.0) || mesh_->triangles.empty()) return false;
  const glm::dvec3 origin = fromMm - centreMm_;
  const glm::dvec3 direction = d / length;
  RTCRay ray;
  ray.org_x = float(origin.x);
  ray.org_y = float(origin.y);
  ray.org_z = float(origin.z);
  ray.tnear = 0.f;
  ray.dir_x = float(direction.x);
  ray.dir_y = float(direction.y);
  ray.dir_z = float(direction.z);
  ray.time = 0.f;
  ray.tfar = float(length);
  ray.mask = 0xffffffffu;
  ray.id = 0;
  ray.flags = 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(scene_.get(), &context, &ray);
  return ray.tfar < 0.f;  // Embree sets it to -inf on a hit
}

}  // namespace osteon::geometry
