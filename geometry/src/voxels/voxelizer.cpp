#include "osteon/geometry/voxels/voxelizer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "axis_pass.h"
#include "column_ray.h"
#include "osteon/core/constants.h"
#include "osteon/core/error.h"
#include "osteon/core/memory.h"
#include "osteon/core/number_text.h"
#include "osteon/core/option_error.h"
#include "osteon/core/timing.h"
#include "osteon/geometry/io/units.h"
#include "osteon/geometry/voxels/embree_scene.h"

namespace osteon::geometry {

using detail::AxisPass;
using detail::runAxisPass;

namespace {

Fill median3(Fill a, Fill b, Fill c) {
  return std::max(std::min(a, b), std::min(std::max(a, b), c));
}

// Robust mode: each voxel takes the median of the axes that could see it (the mean of two,
// or the single one), and voxels whose votes differ by more than half a voxel are counted.
std::uint64_t combineAxes(const VoxelGrid (&axes)[3], const std::vector<std::uint8_t> (&known)[3],
                          VoxelGrid& out) {
  const glm::ivec3 dims = out.dims();
  std::atomic<std::uint64_t> disagreeing{0};
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, out.brickCount()),
      [&](const tbb::blocked_range<std::size_t>& range) {
        std::uint64_t localDisagree = 0;
        for (std::size_t brick = range.begin(); brick != range.end(); ++brick) {
          const glm::ivec3 lo = out.brickCoord(brick) * kBrickEdge;
          const glm::ivec3 hi = glm::min(lo + kBrickEdge, dims);
          Fill values[VoxelGrid::kBrickVoxels] = {};
          bool uniform = true;
          for (int z = lo.z; z < hi.z; ++z)
            for (int y = lo.y; y < hi.y; ++y)
              for (int x = lo.x; x < hi.x; ++x) {
                const glm::ivec3 ijk(x, y, z);
                Fill vote[3];
                int n = 0;
                for (int a = 0; a < 3; ++a) {
                  const int u = (a + 1) % 3;
                  const int v = (a + 2) % 3;
                  if (known[a][std::size_t(ijk[u]) + std::size_t(dims[u]) * std::size_t(ijk[v])]) {
                    vote[n++] = axes[a].fill(ijk);
                  }
                }
                Fill value = 0;
                if (n == 3) value = median3(vote[0], vote[1], vote[2]);
                if (n == 2) {  // mean of two, kept on the 1/255 steps
                  value = Fill((int(vote[0] / kFillPerStep) + int(vote[1] / kFillPerStep) + 1) / 2 *
                               kFillPerStep);
                }
                if (n == 1) value = vote[0];
                if (n >= 2) {
                  const Fill lowest = *std::min_element(vote, vote + n);
                  const Fill highest = *std::max_element(vote, vote + n);
                  if (highest - lowest > kFillHalf) ++localDisagree;
                }
                const int local = VoxelGrid::voxelInBrick(ijk - lo);
                values[local] = value;
                if (value != values[VoxelGrid::voxelInBrick({0, 0, 0})]) uniform = false;
              }
          if (uniform) {
            out.setBrickUniform(brick, values[0], 0);
          } else {
            VoxelGrid::Brick& b = out.materialiseBrick(brick);
            std::copy(std::begin(values), std::end(values), b.fill.begin());
          }
        }
        disagreeing += localDisagree;
      });
  return disagreeing.load();
}

// "<mesh>: a 1 x 2 x 3 mm mesh at <voxel> mm voxels": the start of every size complaint.
std::string meshAtVoxelSize(const TriangleMesh& mesh, const VoxelizeOptions& options) {
  const glm::dvec3 e = bounds(mesh).extentMm();
  std::ostringstream s;
  s << (options.meshName.empty() ? std::string("mesh") : options.meshName) << ": a " << e.x << " x "
    << e.y << " x " << e.z << " mm mesh at "
    << (options.voxelSizeGiven ? optionRef("voxelSizeMm") + " " : std::string("voxels of "))
    << options.voxelSizeMm << " mm";
  return s.str();
}

std::string adviceFor(const TriangleMesh& mesh, const VoxelizeOptions& options) {
  const glm::dvec3 e = bounds(mesh).extentMm();
  const std::string advice = unitsAdvice(std::max({e.x, e.y, e.z}), options.loadScaleToMm);
  return advice.empty() ? "" : "; " + advice;
}

// Peak memory of a voxelization: the brick table, plus the bricks the surface passes through
// (uniform bricks hold no arrays), times the working copies of a run. The constants fit the
// humerus from 0.4 to 0.05 mm (docs/performance.md, "Refused up front").
double estimatePeakBytes(const TriangleMesh& mesh, double voxelSizeMm) {
  const glm::dvec3 bricks =
      glm::ceil((bounds(mesh).extentMm() / voxelSizeMm + 3.0) / double(kBrickEdge));
  const double slots = bricks.x * bricks.y * bricks.z;
  double areaMm2 = 0.0;
  for (const glm::u32vec3& t : mesh.triangles) {
    const glm::dvec3 &a = mesh.positionsMm[t.x], &b = mesh.positionsMm[t.y],
                     &c = mesh.positionsMm[t.z];
    areaMm2 += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  const double brickAreaMm2 = (kBrickEdge * voxelSizeMm) * (kBrickEdge * voxelSizeMm);
  const double surfaceBricks = std::min(slots, 2.5 * areaMm2 / brickAreaMm2);
  const double gridBytes = slots * double(sizeof(void*) + sizeof(Fill) + sizeof(Density) + 1) +
                           surfaceBricks * double(sizeof(VoxelGrid::Brick));
  return 3.0 * gridBytes;
}

// Before any ray is cast: a voxel larger than the whole mesh cannot sample it (and huge
// coordinates along the rays would leave Embree's valid range), and a grid past the voxel
// limit or this machine's memory cannot be held.
void checkVoxelSizeFits(const TriangleMesh& mesh, const VoxelizeOptions& options) {
  const double vs = options.voxelSizeMm;
  if (!std::isfinite(vs) || vs <= 0.0) return;  // makeGridFor names the value
  const glm::dvec3 e = bounds(mesh).extentMm();
  const double largest = std::max({e.x, e.y, e.z});
  if (vs > largest) {
    throw InputError(meshAtVoxelSize(mesh, options) +
                     ": the voxel is larger than the mesh (a voxel size below " +
                     numberText(largest) + " mm is needed)" + adviceFor(mesh, options));
  }
  const glm::dvec3 cells = glm::ceil(e / vs) + 3.0;
  const double voxels = cells.x * cells.y * cells.z;
  const double peakBytes = estimatePeakBytes(mesh, vs);
  if (!(voxels <= double(VoxelGrid::kMaxVoxels))) {
    std::ostringstream s;
    s << meshAtVoxelSize(mesh, options) << " would need " << voxels
      << " voxels (limit 2^32) and about " << memoryText(peakBytes) << " of memory"
      << adviceFor(mesh, options);
    if (options.voxelSizeGiven) s << "; use a larger " << optionRef("voxelSizeMm");
    throw InputError(s.str());
  }
  refuseOverMemory(meshAtVoxelSize(mesh, options), peakBytes,
                   options.voxelSizeGiven ? "use a larger " + optionRef("voxelSizeMm") : "");
}

}  // namespace

VoxelGrid makeGridFor(const TriangleMesh& mesh, double voxelSizeMm, int paddingVoxels) {
  if (!std::isfinite(voxelSizeMm) || voxelSizeMm <= 0.0) {
    throw OptionError("voxelSizeMm", numberText(voxelSizeMm),
                      "must be a positive finite number of millimetres");
  }
  if (paddingVoxels < 1) throw InputError("padding: at least one voxel is needed");
  const Aabb box = bounds(mesh);
  // Voxel faces lie on the world lattice of this voxel size (multiples of it from the mesh's
  // own origin), so grids of sizes VS and VS / 2^k nest: a refined voxel's sub-voxels are the
  // finer grid's voxels, and forces at one sample size sample the same points in static and
  // dynamic mode, whatever the bounding box.
  const glm::dvec3 first = glm::floor(box.minMm / voxelSizeMm) - double(paddingVoxels);
  const glm::dvec3 cells = glm::ceil(box.maxMm / voxelSizeMm) + double(paddingVoxels) - first;
  const double voxels = cells.x * cells.y * cells.z;
  const glm::dvec3 bricks = glm::ceil(cells / double(VoxelGrid::kBrickSize));
  const double brickVoxels = bricks.x * bricks.y * bricks.z * VoxelGrid::kBrickVoxels;
  if (!(voxels <= double(VoxelGrid::kMaxVoxels)) ||
      !(brickVoxels <= double(VoxelGrid::kMaxVoxels))) {
    std::ostringstream s;
    s << optionRef("voxelSizeMm") << " " << voxelSizeMm << ": a " << box.extentMm().x << " x "
      << box.extentMm().y << " x " << box.extentMm().z << " mm mesh would need " << voxels
      << " voxels (limit 2^32); use a larger voxel size";
    throw InputError(s.str());
  }
  const glm::ivec3 dims(cells);
  return VoxelGrid(dims, first * voxelSizeMm, voxelSizeMm);
}

VoxelGrid voxelize(const TriangleMesh& mesh, const VoxelizeOptions& options, VoxelizeStats* stats) {
  const Clock::time_point start = Clock::now();
  if (options.raysPerAxis < 1 || options.raysPerAxis > 16) {
    throw OptionError("raysPerAxis", std::to_string(options.raysPerAxis),
                      "rays per column axis must be 1..16");
  }
  validateDensityRule(options.density);
  checkVoxelSizeFits(mesh, options);
  VoxelGrid grid = makeGridFor(mesh, options.voxelSizeMm, options.paddingVoxels);
  VoxelizeStats local;

  const int outwardSign = detail::outwardSignOf(mesh);
  local.orientedMesh = outwardSign != 0;

  Clock::time_point phase = Clock::now();
  const EmbreeScene scene(mesh);
  local.bvhMs = msSince(phase);

  phase = Clock::now();
  const glm::ivec3 dims = grid.dims();
  const auto runAxis = [&](int axis, VoxelGrid& target, std::vector<std::uint8_t>& known) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    known.assign(std::size_t(dims[u]) * std::size_t(dims[v]), 0);
    AxisPass pass;
    pass.scene = &scene;
    pass.layout = &grid;
    pass.axis = axis;
    pass.raysPerAxis = options.raysPerAxis;
    pass.abstain = options.robust;
    pass.outwardSign = outwardSign;
    pass.out = &target;
    pass.columnKnown = &known;
    runAxisPass(pass);
    local.raysCast += pass.raysCast;
    local.raysRetried += pass.raysRetried;
    local.raysUnresolved += pass.raysUnresolved;
    local.raysWinding += pass.raysWinding;
    local.abstainedColumns += pass.abstainedColumns;
  };

  if (!options.robust) {
    std::vector<std::uint8_t> known;
    runAxis(2, grid, known);  // columns along z, as the seed projects
    local.raysMs = msSince(phase);
  } else {
    VoxelGrid axes[3] = {VoxelGrid(dims, grid.originMm(), grid.voxelSizeMm()),
                         VoxelGrid(dims, grid.originMm(), grid.voxelSizeMm()),
                         VoxelGrid(dims, grid.originMm(), grid.voxelSizeMm())};
    std::vector<std::uint8_t> known[3];
    for (int a = 0; a < 3; ++a) runAxis(a, axes[a], known[a]);
    local.raysMs = msSince(phase);
    phase = Clock::now();
    local.disagreeingVoxels = combineAxes(axes, known, grid);
    local.combineMs = msSince(phase);
  }
  if (options.requireInside && grid.countVoxels(kFillHalf) == 0) {
    throw InputError(meshAtVoxelSize(mesh, options) +
                     " has no voxel inside it (an open, flat or "
                     "inside-out mesh, or voxels too coarse for it)" +
                     adviceFor(mesh, options));
  }

  phase = Clock::now();
  local.density = assignDensity(grid, scene, options.density);
  local.densityMs = msSince(phase);
  grid.clearDirty();  // a fresh volume has no pending surface updates
  local.totalMs = msSince(start);
  if (stats) *stats = local;
  return grid;
}

}  // namespace osteon::geometry
