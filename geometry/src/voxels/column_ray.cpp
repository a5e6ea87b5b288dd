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
    : scene_(&scene),
      axis_(axis),
      outwardSign_(outwardSign),
      startMm_(startMm),
      lengthMm_(lengthMm),
      toleranceMm_(toleranceMm) {
  hits_.reserve(64);
  collector_.hits = &hits_;
  collector_.axis = axis;
}

void ColumnRay::collect(const RTCFilterFunctionNArguments* args) {
  auto* collector = reinterpret_cast<Collector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    // Embree may hand a packet's rays over one by one: the id says which ray it is.
    std::vector<RayHit>& hits = collector->hits[RTCRayN_id(args->ray, args->N, i)];
    float ng = 0.f;
    switch (collector->axis) {
      case 0:
        ng = RTCHitN_Ng_x(args->hit, args->N, i);
        break;
      case 1:
        ng = RTCHitN_Ng_y(args->hit, args->N, i);
        break;
      default:
        ng = RTCHitN_Ng_z(args->hit, args->N, i);
        break;
    }
    hits.push_back({double(t), ng > 0.f ? 1 : (ng < 0.f ? -1 : 0)});
    args->valid[i] = 0;  // reject, so traversal goes on and reports every hit
  }
}

void ColumnRay::castOnce(double uMm, double vMm, double jitterMm, int attempt) {
  const int u = (axis_ + 1) % 3;
  const int v = (axis_ + 2) % 3;
  const glm::dvec3 centre = scene_->centreMm();
  // The scene is stored around its centre, so rays start there in single precision too; the
  // start's rounding is added back to every hit distance.
  const float startLocal = float(startMm_ - centre[axis_]);
  const double startShift = (double(startLocal) + centre[axis_]) - startMm_;
  // A re-cast moves a little, on a spiral, off whatever edge or vertex the ray grazed.
  // (The first cast adds exactly 0.0 without calling cos and sin.)
  const double jitter = (attempt % 4) * jitterMm;
  const double du = attempt == 0 ? 0.0 : jitter * std::cos(attempt * 2.4);
  const double dv = attempt == 0 ? 0.0 : jitter * std::sin(attempt * 2.4);
  float org[3];
  org[axis_] = startLocal;
  org[u] = float(uMm - centre[u] + du);
  org[v] = float(vMm - centre[v] + dv);
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
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.ray.time = 0.f;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcInitIntersectContext(&collector_.context);
  collector_.context.filter = collect;
  collector_.hits = &hits_;
  hits_.clear();
  rtcIntersect1(scene_->handle(), &collector_.context, &rh);
  for (RayHit& h : hits_) h.t += startShift;
}

RayOutcome ColumnRay::finish(double uMm, double vMm, double jitterMm, int attempt,
                             std::vector<Interval>& intervals, int& attempts) {
  // Up to four casts with the mesh's orientation checked, then one by parity alone (a mesh
  // with an inverted component is still a solid to parity).
  RayOutcome outcome = RayOutcome::Unresolved;
  for (;; ++attempt) {
    const int sign = attempt < 4 ? outwardSign_ : 0;
    outcome = classifyRay(hits_, sign, toleranceMm_, intervals);
    if (outcome != RayOutcome::Unresolved) break;
    if (attempt + 1 >= 5 || (attempt + 1 == 4 && outwardSign_ == 0)) break;
    castOnce(uMm, vMm, jitterMm, attempt + 1);
    ++attempts;
  }
  return outcome;
}

RayOutcome ColumnRay::cast(double uMm, double vMm, double jitterMm,
                           std::vector<Interval>& intervals, int& attempts) {
  castOnce(uMm, vMm, jitterMm, 0);
  attempts = 1;
  return finish(uMm, vMm, jitterMm, 0, intervals, attempts);
}

void ColumnRay::castPacket(int count, const double* uMm, const double* vMm, double jitterMm,
                           bool pairUnresolved, std::vector<Interval>* intervals,
                           RayOutcome* outcomes, int* attempts) {
  const int u = (axis_ + 1) % 3;
  const int v = (axis_ + 2) % 3;
  const glm::dvec3 centre = scene_->centreMm();
  const float startLocal = float(startMm_ - centre[axis_]);
  const double startShift = (double(startLocal) + centre[axis_]) - startMm_;
  // The same rays as castOnce(..., 0), lane by lane.
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[kPacket];
  for (int i = 0; i < kPacket; ++i) {
    const bool on = i < count;
    valid[i] = on ? -1 : 0;
    float org[3];
    org[axis_] = startLocal;
    org[u] = on ? float(uMm[i] - centre[u] + 0.0) : 0.f;
    org[v] = on ? float(vMm[i] - centre[v] + 0.0) : 0.f;
    rh.ray.org_x[i] = org[0];
    rh.ray.org_y[i] = org[1];
    rh.ray.org_z[i] = org[2];
    rh.ray.dir_x[i] = axis_ == 0 ? 1.f : 0.f;
    rh.ray.dir_y[i] = axis_ == 1 ? 1.f : 0.f;
    rh.ray.dir_z[i] = axis_ == 2 ? 1.f : 0.f;
    rh.ray.tnear[i] = 0.f;
    rh.ray.tfar[i] = float(lengthMm_);
    rh.ray.mask[i] = 0xffffffffu;
    rh.ray.id[i] = unsigned(i);
    rh.ray.flags[i] = 0;
    rh.ray.time[i] = 0.f;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    packetHits_[i].clear();
  }
  rtcInitIntersectContext(&collector_.context);
  collector_.context.filter = collect;
  collector_.hits = packetHits_;
  rtcIntersect16(valid, scene_->handle(), &collector_.context, &rh);
  for (int i = 0; i < count; ++i) {
    hits_.swap(packetHits_[i]);
    for (RayHit& h : hits_) h.t += startShift;
    attempts[i] = 1;
    outcomes[i] = finish(uMm[i], vMm[i], jitterMm, 0, intervals[i], attempts[i]);
    if (outcomes[i] == RayOutcome::Unresolved && pairUnresolved) pairByParity(hits_, intervals[i]);
  }
}

}  // namespace osteon::geometry::detail
