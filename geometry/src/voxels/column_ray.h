// Axis-aligned rays through a mesh with every hit collected and classified (seed 3.2), shared
// by the voxelizer and the fine (sub-voxel) sampling of refinement.
#pragma once

#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "ray_classify.h"

namespace osteon::geometry::detail {

// +1 for a consistently outward-oriented mesh, -1 for an inward one, 0 when orientation
// cannot be trusted (then rays are classified by parity alone).
int outwardSignOf(const TriangleMesh& mesh);

// One per thread: owns its hit buffer.
class ColumnRay {
 public:
  // Rays along `axis` start at coordinate startMm on that axis and run lengthMm. Hits closer
  // than toleranceMm are one crossing (a surface seen twice through a shared edge).
  ColumnRay(const EmbreeScene& scene, int axis, int outwardSign, double startMm, double lengthMm,
            double toleranceMm);

  // Casts at (uMm, vMm) on the two other axes ((axis+1)%3, (axis+2)%3). An odd or
  // inconsistent hit list is re-cast up to three times, moved by multiples of jitterMm, and
  // then once more classified by parity alone.
  // intervals receive the inside spans as distances from startMm. attempts counts casts.
  RayOutcome cast(double uMm, double vMm, double jitterMm, std::vector<Interval>& intervals,
                  int& attempts);
  // The merged hits of the last cast (for a best-effort parity pairing when unresolved).
  const std::vector<RayHit>& hits() const { return hits_; }

  // Up to kPacket rays at once: their first casts go to Embree as one packet, the re-casts
  // of any unresolved one as single rays, so each ray's intervals, outcome and attempts are
  // those cast() gives it. When pairUnresolved, an unresolved ray's intervals are its last
  // hits paired by parity (what the voxelizer does with hits() after cast()).
  static constexpr int kPacket = 16;
  void castPacket(int count, const double* uMm, const double* vMm, double jitterMm,
                  bool pairUnresolved, std::vector<Interval>* intervals, RayOutcome* outcomes,
                  int* attempts);

 private:
  struct Collector {
    RTCIntersectContext context;  // first: Embree hands the filter a pointer to it
    std::vector<RayHit>* hits;    // indexed by the ray's id
    int axis;
  };
  static void collect(const RTCFilterFunctionNArguments* args);
  // Re-casts (attempts from `attempt` on) after a first cast whose hits are in hits_.
  RayOutcome finish(double uMm, double vMm, double jitterMm, int attempt,
                    std::vector<Interval>& intervals, int& attempts);
  // One cast with the given attempt's jitter; the shifted raw hits land in hits_.
  void castOnce(double uMm, double vMm, double jitterMm, int attempt);

  const EmbreeScene* scene_;
  int axis_;
  int outwardSign_;
  double startMm_;
  double lengthMm_;
  double toleranceMm_;
  std::vector<RayHit> hits_;
  std::vector<RayHit> packetHits_[kPacket];
  Collector collector_;
};

}  // namespace osteon::geometry::detail
