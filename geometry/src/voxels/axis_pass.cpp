#include "axis_pass.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "column_ray.h"
#include "osteon/core/constants.h"

namespace osteon::geometry::detail {

namespace {

// The columns some triangle's bounding box reaches across the rays along `a` (widened far
// beyond Embree's float rounding), (u, v) bitmap, u fastest. A ray in any other column can hit
// nothing: no hits is an even, resolved ray with no inside interval, so such a column is
// counted as cast and left empty.
std::vector<std::uint8_t> reachableColumns(const TriangleMesh& mesh, const VoxelGrid& grid, int a) {
  const int u = (a + 1) % 3;
  const int v = (a + 2) % 3;
  const glm::ivec3 dims = grid.dims();
  const double vs = grid.voxelSizeMm();
  const glm::dvec3 origin = grid.originMm();
  const std::size_t columns = std::size_t(dims[u]) * std::size_t(dims[v]);
  std::vector<std::uint8_t> reachable(columns, 0);
  const double margin = 1e-2 * vs + 1e-3;
  const auto columnOf = [&](double coordMm, int c) {
    const double g = std::floor((coordMm - origin[c]) / vs);
    return int(std::clamp(g, 0.0, double(dims[c] - 1)));
  };
  for (const glm::u32vec3& t : mesh.triangles) {
    const glm::dvec3& p0 = mesh.positionsMm[t.x];
    const glm::dvec3& p1 = mesh.positionsMm[t.y];
    const glm::dvec3& p2 = mesh.positionsMm[t.z];
    const int u0 = columnOf(std::min({p0[u], p1[u], p2[u]}) - margin, u);
    const int u1 = columnOf(std::max({p0[u], p1[u], p2[u]}) + margin, u);
    const int v0 = columnOf(std::min({p0[v], p1[v], p2[v]}) - margin, v);
    const int v1 = columnOf(std::max({p0[v], p1[v], p2[v]}) + margin, v);
    for (int jv = v0; jv <= v1; ++jv)
      for (int ju = u0; ju <= u1; ++ju) {
        reachable[std::size_t(ju) + std::size_t(dims[u]) * std::size_t(jv)] = 1;
      }
  }
  return reachable;
}

// One thread's work of an axis pass: a column of bricks at a time, its voxel columns' rays
// cast and accumulated, then the bricks stored.
class ColumnWorker {
 public:
  ColumnWorker(AxisPass& pass, const std::vector<std::uint8_t>& reachable)
      : pass_(pass),
        grid_(*pass.layout),
        reachable_(reachable),
        a_(pass.axis),
        u_((a_ + 1) % 3),
        v_((a_ + 2) % 3),
        dims_(grid_.dims()),
        vs_(grid_.voxelSizeMm()),
        origin_(grid_.originMm()),
        acc_(static_cast<std::size_t>(dims_[a_]), 0.f),
        column_(std::size_t(kBrickEdge * kBrickEdge) * std::size_t(dims_[a_]), 0),
        // Coincident hits: far below a voxel, and no more than 0.1 um on any grid.
        ray_(*pass.scene, a_, pass.outwardSign, grid_.originMm()[a_] - grid_.voxelSizeMm(),
             (dims_[a_] + 2) * grid_.voxelSizeMm(), std::min(1e-4, 1e-3 * grid_.voxelSizeMm())) {}

  void brickColumn(int bu, int bv) {
    std::fill(std::begin(touchedFirst_), std::end(touchedFirst_), dims_[a_]);
    std::fill(std::begin(touchedLast_), std::end(touchedLast_), -1);
    for (int lv = 0; lv < kBrickEdge; ++lv) {
      const int iv = bv * kBrickEdge + lv;
      if (iv >= dims_[v_]) break;
      for (int lu = 0; lu < kBrickEdge; ++lu) {
        const int iu = bu * kBrickEdge + lu;
        if (iu >= dims_[u_]) break;
        voxelColumn(iu, iv, std::size_t(lu + kBrickEdge * lv));
      }
    }
    storeBricks(bu, bv);
  }

  // Adds this worker's counts to the pass's.
  void publish() {
    pass_.raysCast += cast_;
    pass_.raysRetried += retried_;
    pass_.raysUnresolved += unresolved_;
    pass_.raysWinding += winding_;
    pass_.abstainedColumns += abstained_;
  }

 private:
  // The rays of voxel column (iu, iv), accumulated into its fills (colIndex: its place in the
  // brick column).
  void voxelColumn(int iu, int iv, std::size_t colIndex) {
    const int R = pass_.raysPerAxis;
    int kFirst = dims_[a_], kLast = -1;  // voxels of acc written for this column
    int votes = 0;
    const bool unreachable =
        !reachable_[std::size_t(iu) + std::size_t(dims_[u_]) * std::size_t(iv)];
    if (unreachable) {
      cast_ += std::uint64_t(R) * std::uint64_t(R);
      votes = R * R;
    }
    // The column's rays, sv-major as always, cast in packets; each ray is then accumulated in
    // that order.
    for (int first = 0; !unreachable && first < R * R; first += detail::ColumnRay::kPacket) {
      const int count = std::min(detail::ColumnRay::kPacket, R * R - first);
      for (int i = 0; i < count; ++i) {
        const int sv = (first + i) / R;
        const int su = (first + i) % R;
        // Stratified samples, nudged off rational positions so rays do not run exactly along
        // the edges and faces of axis-aligned meshes.
        const double fu = (su + 0.5 + 0.0061803) / R;
        const double fv = (sv + 0.5 + 0.0041421) / R;
        packetU_[i] = origin_[u_] + (iu + fu) * vs_;
        packetV_[i] = origin_[v_] + (iv + fv) * vs_;
      }
      ray_.castPacket(count, packetU_, packetV_, 2e-3 * vs_ / R, !pass_.abstain, packetIntervals_,
                      packetOutcomes_, packetAttempts_);
      for (int i = 0; i < count; ++i) {
        const detail::RayOutcome outcome = packetOutcomes_[i];
        ++cast_;
        retried_ += std::uint64_t(packetAttempts_[i] - 1);
        if (outcome == detail::RayOutcome::Winding) ++winding_;
        if (outcome == detail::RayOutcome::Unresolved) {
          ++unresolved_;
          if (pass_.abstain) continue;  // (otherwise paired by parity: best effort)
        }
        ++votes;
        accumulate(packetIntervals_[i], kFirst, kLast);
      }
    }
    if (votes == 0) {
      ++abstained_;
      for (int k = kFirst; k <= kLast; ++k) acc_[std::size_t(k)] = 0.f;
      return;  // column stays unknown
    }
    (*pass_.columnKnown)[std::size_t(iu) + std::size_t(dims_[u_]) * std::size_t(iv)] = 1;
    if (kFirst > kLast) return;  // no voxel touched: empty
    touchedFirst_[colIndex] = kFirst;
    touchedLast_[colIndex] = kLast;
    Fill* dst = column_.data() + colIndex * std::size_t(dims_[a_]);
    // Fill in 1/255 steps (what 4 x 4 rays resolve), stored in fill units; rounded half away
    // from zero as lround does (x >= 0 here, and x - floor(x) is exact in float).
    const float scale = float(kFillSteps) / float(votes);
    for (int k = kFirst; k <= kLast; ++k) {
      const float x = acc_[std::size_t(k)] * scale;
      acc_[std::size_t(k)] = 0.f;
      long steps = long(x);
      if (x - float(steps) >= 0.5f) ++steps;
      dst[k] = Fill(std::clamp(steps, 0L, long(kFillSteps)) * kFillPerStep);
    }
  }

  // Exact overlap of each inside interval with the voxels of the column: partial at its two
  // end voxels, exactly 1 for every voxel between them (ray by ray, in the same order, so each
  // voxel's float sum is the same).
  void accumulate(const std::vector<detail::Interval>& intervals, int& kFirst, int& kLast) {
    for (const detail::Interval& iv01 : intervals) {
      const double s0 = std::max(0.0, (iv01.t0 - vs_) / vs_);
      const double s1 = std::min(double(dims_[a_]), (iv01.t1 - vs_) / vs_);
      if (s1 <= s0) continue;
      const int k0 = int(s0);
      const int k1 = std::min(int(s1), dims_[a_] - 1);
      kFirst = std::min(kFirst, k0);
      kLast = std::max(kLast, k1);
      const double firstOverlap = std::min(s1, k0 + 1.0) - s0;
      if (firstOverlap > 0.0) acc_[std::size_t(k0)] += float(firstOverlap);
      if (k1 == k0) continue;
      float* inner = acc_.data() + k0 + 1;
      for (int n = k1 - k0 - 1; n > 0; --n) *inner++ += 1.f;
      const double lastOverlap = std::min(s1, k1 + 1.0) - double(k1);
      if (lastOverlap > 0.0) acc_[std::size_t(k1)] += float(lastOverlap);
    }
  }

  Fill valueAt(int col, int k) const {
    return k >= touchedFirst_[col] && k <= touchedLast_[col]
               ? column_[std::size_t(col) * std::size_t(dims_[a_]) + std::size_t(k)]
               : Fill(0);
  }

  // Stores the column of bricks: uniform where every voxel agrees, arrays otherwise.
  void storeBricks(int bu, int bv) {
    // Voxel-index strides inside a brick along the column axis and the two across it.
    const int stride[3] = {1, kBrickEdge, kBrickEdge * kBrickEdge};
    const int nu = std::min(kBrickEdge, dims_[u_] - bu * kBrickEdge);
    const int nv = std::min(kBrickEdge, dims_[v_] - bv * kBrickEdge);
    for (int ba = 0; ba < grid_.brickDims()[a_]; ++ba) {
      glm::ivec3 bc;
      bc[a_] = ba;
      bc[u_] = bu;
      bc[v_] = bv;
      const std::size_t brick = grid_.brickIndex(bc);
      const int k0 = ba * kBrickEdge;
      const int k1 = std::min(k0 + kBrickEdge, dims_[a_]);
      const Fill first = valueAt(0, k0);
      bool uniform = true;
      for (int lv = 0; lv < nv && uniform; ++lv)
        for (int lu = 0; lu < nu && uniform; ++lu) {
          const int col = lu + kBrickEdge * lv;
          if (k1 <= touchedFirst_[col] || k0 > touchedLast_[col]) {
            uniform = first == 0;  // the whole segment is empty
            continue;
          }
          for (int k = k0; k < k1; ++k) {
            if (valueAt(col, k) != first) {
              uniform = false;
              break;
            }
          }
        }
      if (uniform) {
        pass_.out->setBrickUniform(brick, first, 0);
        continue;
      }
      VoxelGrid::Brick& b = pass_.out->materialiseBrick(brick);
      for (int lv = 0; lv < nv; ++lv)
        for (int lu = 0; lu < nu; ++lu) {
          const int col = lu + kBrickEdge * lv;
          const int base = lu * stride[u_] + lv * stride[v_];
          for (int k = k0; k < k1; ++k) {
            b.fill[std::size_t(base + (k - k0) * stride[a_])] = valueAt(col, k);
          }
        }
    }
  }

  AxisPass& pass_;
  const VoxelGrid& grid_;
  const std::vector<std::uint8_t>& reachable_;
  const int a_, u_, v_;
  const glm::ivec3 dims_;
  const double vs_;
  const glm::dvec3 origin_;
  std::vector<detail::Interval> packetIntervals_[detail::ColumnRay::kPacket];
  double packetU_[detail::ColumnRay::kPacket], packetV_[detail::ColumnRay::kPacket];
  detail::RayOutcome packetOutcomes_[detail::ColumnRay::kPacket];
  int packetAttempts_[detail::ColumnRay::kPacket];
  std::vector<float> acc_;    // zero between columns
  std::vector<Fill> column_;  // the brick column's fills, voxel column by voxel column
  // Per voxel column of the brick column: the voxels [first, last] any inside interval
  // touched; the column's other voxels are empty (first > last: all empty).
  int touchedFirst_[kBrickEdge * kBrickEdge];
  int touchedLast_[kBrickEdge * kBrickEdge];
  detail::ColumnRay ray_;
  std::uint64_t cast_ = 0, retried_ = 0, unresolved_ = 0, winding_ = 0, abstained_ = 0;
};

}  // namespace

void runAxisPass(AxisPass& pass) {
  const int u = (pass.axis + 1) % 3;
  const int v = (pass.axis + 2) % 3;
  const glm::ivec3 brickDims = pass.layout->brickDims();
  const std::size_t brickColumns = std::size_t(brickDims[u]) * std::size_t(brickDims[v]);
  const std::vector<std::uint8_t> reachable =
      reachableColumns(pass.scene->mesh(), *pass.layout, pass.axis);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, brickColumns),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      ColumnWorker worker(pass, reachable);
                      for (std::size_t bcol = range.begin(); bcol != range.end(); ++bcol) {
                        worker.brickColumn(int(bcol % std::size_t(brickDims[u])),
                                           int(bcol / std::size_t(brickDims[u])));
                      }
                      worker.publish();
                    });
}

}  // namespace osteon::geometry::detail
