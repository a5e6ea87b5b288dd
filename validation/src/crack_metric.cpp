#include "osteon/validation/crack_metric.h"

#include <atomic>
#include <limits>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "osteon/core/error.h"
#include "osteon/core/option_error.h"
#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/voxels/embree_scene.h"
#include "osteon/image/image_writer.h"

namespace osteon::validation {

namespace {

// Sub-pixel offsets, irrational-ish: a sample on a regular mesh's shared edge or vertex would
// let a float rounding decide between the two faces (or neither). Embree's robust mode is
// watertight, but a closed mesh must never show a false red pixel, so stay off the lattice.
constexpr double kOffsetU = 0.5 + 0.0731;
constexpr double kOffsetV = 0.5 + 0.0419;

}  // namespace

CrackMetric measureCracks(const geometry::TriangleMesh& mesh, const CrackMetricOptions& options) {
  if (options.pixels < 16 || options.pixels > 4096) {
    throw OptionError("crackPixels", std::to_string(options.pixels),
                      "pixels per side must be 16..4096");
  }
  if (mesh.triangles.empty()) throw InputError("crack metric: the mesh has no triangles");
  const geometry::EmbreeScene scene(mesh);
  const geometry::Aabb box = geometry::bounds(mesh);
  const glm::dvec3 centre = 0.5 * (box.minMm + box.maxMm);
  const glm::dvec3 extent = box.maxMm - box.minMm;
  const int n = options.pixels;
  CrackMetric metric;
  metric.pixels = n;
  for (int view = 0; view < 6; ++view) {
    const int axis = view / 2;
    const double sign = view % 2 == 0 ? 1.0 : -1.0;  // seen from +axis (looking along -axis)
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const double side = 1.02 * std::max({extent[ua], extent[va], 1e-6});  // square, a margin round
    CrackView& out = metric.views[std::size_t(view)];
    out.name = std::string(sign > 0 ? "+" : "-") + char('x' + axis);
    if (options.keepImages) out.rgb.assign(std::size_t(n) * std::size_t(n) * 3, 0);
    std::atomic<std::uint64_t> white{0}, red{0};
    tbb::parallel_for(0, n, [&](int row) {
      std::uint64_t w = 0, r = 0;
      for (int col = 0; col < n; ++col) {
        glm::dvec3 origin = centre;
        origin[ua] += (double(col) + kOffsetU) / n * side - 0.5 * side;
        origin[va] += 0.5 * side - (double(row) + kOffsetV) / n * side;  // top row first
        origin[axis] = sign > 0 ? box.maxMm[axis] + 1.0 : box.minMm[axis] - 1.0;
        glm::dvec3 dir(0.0);
        dir[axis] = -sign;
        const glm::dvec3 o = origin - scene.centreMm();
        RTCRayHit rh{};
        rh.ray.org_x = float(o.x);
        rh.ray.org_y = float(o.y);
        rh.ray.org_z = float(o.z);
        rh.ray.dir_x = float(dir.x);
        rh.ray.dir_y = float(dir.y);
        rh.ray.dir_z = float(dir.z);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = 0xffffffffu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        rtcIntersect1(scene.handle(), &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;  // background
        // Embree's geometric normal follows the winding (outward for an outward mesh): the
        // ray meets a front face when it runs against it.
        const double facing =
            double(rh.hit.Ng_x) * dir.x + double(rh.hit.Ng_y) * dir.y + double(rh.hit.Ng_z) * dir.z;
        const bool front = facing < 0.0;
        (front ? w : r) += 1;
        if (options.keepImages) {
          std::uint8_t* px = &out.rgb[(std::size_t(row) * std::size_t(n) + std::size_t(col)) * 3];
          px[0] = 255;
          px[1] = front ? 255 : 0;
          px[2] = front ? 255 : 0;
        }
      }
      white += w;
      red += r;
    });
    out.white = white;
    out.red = red;
    metric.white += out.white;
    metric.red += out.red;
  }
  return metric;
}

std::vector<std::string> writeCrackImages(const CrackMetric& metric, const std::string& dir) {
  std::vector<std::string> paths;
  for (const CrackView& view : metric.views) {
    if (view.rgb.empty()) throw std::logic_error("writeCrackImages: measureCracks kept no images");
    const std::string path = dir + "/cracks_" + view.name + ".png";
    geometry::OutputFile file(path);
    const std::string error =
        image::writeImageU8(file.tempPath(), metric.pixels, metric.pixels, 3, view.rgb.data());
    if (!error.empty()) throw InputError(path + ": cannot write the crack image (" + error + ")");
    file.commit();
    paths.push_back(path);
  }
  return paths;
}

}  // namespace osteon::validation
