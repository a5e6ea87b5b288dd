#include "column_ray.h"

#include <cmath>

namespace osteon::geometry::detail {

int outwardSignOf(const TriangleMesh& mesh) {
  // Hit facing can check each ray only when the mesh is closed and every edge is used once
  // each way; an open mesh's signed volume depends on where it is measured from.
  const MeshTopology topology = analyzeTopology(mesh);
  if (!topology.closed() || !topology.consistentlyOriented()) return 0;
  const double volume = signedVolumeMm3(mesh);
  if (volume == 0.0) return 0;
  return volume > 0.0 ? 1 : -1;
}

ColumnRay::ColumnRay(const EmbreeScene& scene, int axis, int outwardSign, double startMm,
                     double lengthMm, double toleranceMm)
    : scene_(&scene), axis_(axis), outwardSign_(outwardSign), startMm_(startMm),
      lengthMm_(lengthMm), toleranceMm_(toleranceMm) {
  hits_.reserve(64);
  collector_.hits = &hits_;
  collector_.axis = axis;
}

void ColumnRay::collect(const RTCFilterFunctionNArguments* args) {
  auto* collector = reinterpret_cast<Collector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    float ng = 0.f;
    switch (collector->axis) {
      case 0: ng = RTCHitN_Ng_x(args->hit, args->N, i); break;
      case 1: ng = RTCHitN_Ng_y(args->hit, args->N, i); break;
      default: ng = RTCHitN_Ng_z(args->hit, args->N, i); break;
    }
    collector->hits->push_back({double(t), ng > 0.f ? 1 : (ng < 0.f ? -1 : 0)});
    args->valid[i] = 0;  // reject, so traversal goes on and reports every hit
  }
}

RayOutcome ColumnRay::cast(double uMm, double vMm, double jitterMm,
                           std::vector<Interval>& intervals, int& attempts) {
  const int u = (axis_ + 1) % 3;
  const int v = (axis_ + 2) % 3;
  const glm::dvec3 centre = scene_->centreMm();
  // The scene is stored around its centre, so rays start there in single precision too; the
  // start's rounding is added back to every hit distance.
  const float startLocal = float(startMm_ - centre[axis_]);
  const double startShift = (double(startLocal) + centre[axis_]) - startMm_;
  RayOutcome outcome = RayOutcome::Unresolved;
  attempts = 0;
  // Up to four casts with the mesh's orientation checked, then one by parity alone (a mesh
  // with an inverted component is still a solid to parity).
  for (int attempt = 0; attempt < 5; ++attempt) {
    const int sign = attempt < 4 ? outwardSign_ : 0;
    if (attempt == 4 && outwardSign_ == 0) break;
    // A re-cast moves a little, on a spiral, off whatever edge or vertex the ray grazed.
    const double jitter = (attempt % 4) * jitterMm;
    float org[3];
    org[axis_] = startLocal;
    org[u] = float(uMm - centre[u] + jitter * std::cos(attempt * 2.4));
    org[v] = float(vMm - centre[v] + jitter * std::sin(attempt * 2.4));
    RTCRayHit rh;
    rh.ray.org_x = org[0];
    rh.ray.org_y = org[1];
    rh.ray.org_z = org[2];
    rh.ray.dir_x = axis_ == 0 ? 1.f : 0.f;
    rh.ray.dir_y = axis_ == 1 ? 1.f : 0.f;
    rh.ray.dir_z = axis_ == 2 ? 1.f : 0.f;
    rh.ray.tnear = 0.f;
    rh.ray.tfar = float(lengthMm_);
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcInitIntersectContext(&collector_.context);
    collector_.context.filter = collect;
    hits_.clear();
    rtcIntersect1(scene_->handle(), &collector_.context, &rh);
    ++attempts;
    for (RayHit& h : hits_) h.t += startShift;
    outcome = classifyRay(hits_, sign, toleranceMm_, intervals);
    if (outcome != RayOutcome::Unresolved) break;
  }
  return outcome;
}

}  // namespace osteon::geometry::detail
