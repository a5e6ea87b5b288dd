// One drilling session: the object every front end (the CLI, the viewer, an integrator's
// trainer) drives. It owns the bone and everything built on it (MuJoCo's model/data split in
// spirit: what does not change, the mesh and the options, beside what drilling changes, the
// grid, the hierarchy, the refined voxels and the surface), so no lifetime rule is left to the
// caller. Move-only; moving keeps every internal reference valid.
//
//   Session s = Session::open("default", 1.0, SessionOptions{});   // 1.2 mm, 2 levels, drill
//   (or: auto bone = BoneModel::open(source).bone; Session a(bone, options), b(bone, options);)
//   const DrillPath path = s.portalPath(Portal::FiveOClock).path;
//   RunResult r = s.run(path);                                     // deterministic, 1 kHz
//   const geometry::SurfaceMesh& bone = s.surface();
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/geometry/surface/surface.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/geometry/voxels/voxel_grid.h"
#include "osteon/geometry/voxels/voxelizer.h"
#include "osteon/simulation/coupling.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/runner.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/tool.h"

namespace osteon::geometry {
class DynamicProximityHierarchy;
class FineFillSource;
}  // namespace osteon::geometry

namespace osteon::simulation {

struct BoneSource;  // bone_source.h
struct OpenedBone;

struct SessionOptions {
  // The bone (used by the convenience constructors, which build a BoneModel).
  double voxelSizeMm = 1.2;
  // Voxelization of a mesh (density rule, rays); the voxel size and the names for messages
  // are set from the session's. A mesh whose grid has no voxel inside is refused (InputError).
  geometry::VoxelizeOptions voxelizing;
  // The drilling.
  int levels = 2;  // 0 static, 1 or 2 dynamic (refined near the tool)
  ToolKind tool = ToolKind::Drill;
  ToolOptions toolOptions;
  DrillingOptions drilling;          // its `levels` is replaced by `levels` above
  geometry::SurfaceOptions surface;  // the incremental surface kept by step() and run()
  bool keepSurface = true;           // false: no visual work (faster batch runs)
  // How the commanded pose moves the tool (coupling.h): direct (the seed's scripted paths, the
  // library's default) or through a proxy that bone stops (hands: devices, recordings).
  CouplingMode coupling = CouplingMode::Direct;
  CouplingOptions couplingOptions;
  // The cutting resistance (cutting.h): the seed's eq. (2), or calibrated to published drilling
  // thrust (proxy coupling only: the proxy's feed renders it). Sets the drilling's and the
  // coupling's forceModel.
  ForceModelKind forceModel = ForceModelKind::Seed;
  // The drill's rpm and irrigation where the pose source gives none (paths, devices without a
  // knob): run() and the runtimes start every step with these.
  DrillSettings settings;
};

// How long set-up took, stage by stage, in wall-clock milliseconds (osteon/core/timing.h), so
// integrators and front ends can see where the wait before the first step goes. A stage that
// did not run is 0 (a bone from a grid has no voxelize, density or fine fills stage).
struct SetupTimings {
  double loadMs = 0.0;  // the mesh read and scaled, or the built-in bone built, or the volume read
  double voxelizeMs = 0.0;   // ray projection and fills (the voxelizer without its density pass)
  double densityMs = 0.0;    // cortical / cancellous density (the voxelizer's last pass)
  double fineFillsMs = 0.0;  // level -2 fills sampled from the mesh (sessions with levels 1 or 2)
  double hierarchyMs = 0.0;  // the Dynamic Proximity Hierarchy built over the session's grid
  // The first full surface extraction (keepSurface sessions, and the threaded runtime's visual
  // side): it runs on its own thread beside the first steps, so it is not part of totalMs.
  double surfaceMs = 0.0;
  // Wall time of the set-up before the first step can be taken: the stages above but the
  // surface, and what lies between them (the grid copy, the drilling simulation's pools), so it
  // is never less than any one of them.
  double totalMs = 0.0;
  // From the start of set-up (the bone's load) to the first haptic step taken, and to the full
  // surface being there; 0 until each has happened.
  double firstStepMs = 0.0;
  double surfaceReadyMs = 0.0;
};

// The bytes a session holds, structure by structure (capacity, not just use), and the voxels
// with bone they are counted against (bytesPerVoxel). The bone's grid and fine fills are shared
// by every session drilling that bone; the visual side is the threaded runtime's, when the last
// run was threaded (its own grid copy and surface), else the session's kept surface.
struct SessionMemory {
  std::uint64_t voxels = 0;                  // voxels with bone at set-up (the hierarchy's)
  std::size_t boneGrid = 0;                  // the bone as voxelized (BoneModel)
  std::size_t fineFills = 0;                 // level -2 fills sampled from the mesh (BoneModel)
  std::size_t grid = 0;                      // this session's drilled copy
  std::size_t hierarchy = 0;                 // the Dynamic Proximity Hierarchy
  std::size_t refinement = 0;                // the refined voxels' pool, tables and removal masks
  std::size_t thermal = 0;                   // the heat model (calibrated force model)
  std::size_t visualGrid = 0;                // the threaded runtime's copy of the grid
  geometry::SurfaceUpdater::Memory surface;  // the incremental surface
  std::size_t total() const {
    return boneGrid + fineFills + grid + hierarchy + refinement + thermal + visualGrid +
           surface.total();
  }
};

// The peak memory of a drilling session on this mesh at this voxel size, in bytes: set-up
// (the voxelized grid and its drilled copy, the hierarchy, the fine fills, the first surface)
// and the final multi-resolution surface. It grows with the surface (area / vs^2) and the bone
// (volume / vs^3); the constants fit the peak RSS of `drill default` (levels 2) at 0.54, 0.3,
// 0.2 and 0.15 mm (82, 251, 610 and 1159 MiB) within 3 %; at 0.05 mm it says about 17.5 GB.
// BoneModel refuses a mesh over this machine's memory before voxelizing (refuseOverMemory).
double estimateSessionBytes(const geometry::TriangleMesh& meshMm, double voxelSizeMm);

// What does not change while drilling: the mesh (when there is one), the grid as voxelized,
// and the level -2 fills sampled from the mesh for refinement. Immutable and shared: many
// sessions (every run of an experiment) drill fresh copies of one bone. A bone from a grid (a
// saved grid, a label map, a CT) fits its humeral head to the grid's own surface instead.
class BoneModel {
 public:
  // From a mesh in millimetres. `name` names it in messages (a file, or "default");
  // loadScaleToMm is how it was scaled on loading (to suggest --units in messages); up: the
  // head's end (BoneSource::up). sampleFineFills: sample the level -2 fills (needed for refinement
  // from the mesh).
  static std::shared_ptr<const BoneModel> fromMesh(
      geometry::TriangleMesh meshMm, double voxelSizeMm, const std::string& name = "mesh",
      double loadScaleToMm = 1.0, const geometry::VoxelizeOptions& voxelizing = {},
      bool sampleFineFills = true, const std::optional<glm::dvec3>& up = {});
  // From a source as front ends take it: a mesh file, `default` or a volume (bone_source.h),
  // with what it was read as. Every check of the source is made here.
  static OpenedBone open(const BoneSource& source);
  // Convenience: open() of a mesh argument (a mesh file or `default`), scaled to mm.
  static std::shared_ptr<const BoneModel> open(const std::string& meshArgument, double scaleToMm,
                                               double voxelSizeMm,
                                               const geometry::VoxelizeOptions& voxelizing = {},
                                               bool sampleFineFills = true);
  // From a saved grid: no mesh, so refined voxels split their fill evenly.
  // loadMs: how long reading the grid took, reported by setupTimings().
  static std::shared_ptr<const BoneModel> fromGrid(geometry::VoxelGrid grid,
                                                   const std::string& name = "grid",
                                                   double loadMs = 0.0);

  ~BoneModel();

  const std::string& name() const { return name_; }
  const geometry::TriangleMesh* mesh() const { return mesh_ ? &*mesh_ : nullptr; }
  const geometry::VoxelGrid& grid() const { return grid_; }
  const geometry::FineFillSource* fineFills() const { return fineFills_.get(); }
  // What the humeral head is fitted to and portal paths enter: the mesh, or for a bone without
  // one the grid's crack-free surface in mm (the `mesh` command's), extracted once on first use
  // (safe from any thread): only portal paths pay for it.
  const geometry::TriangleMesh& headMesh() const;
  // The humeral head fitted to headMesh() (seed 4's portals), fitted once on first use (safe
  // from any thread) at the end up() names, or else at the end a sphere fits best. Throws
  // InputError when no end of the bone fits a head, or the fit is no humeral head
  // (checkHumeralHead: one line suggesting --up or an explicit entry point).
  const HumeralHead& humeralHead() const;
  // The up axis the bone was opened with (BoneSource::up), if any.
  const std::optional<glm::dvec3>& up() const { return up_; }
  // The bone's share of set-up: load (open() and fromGrid()'s loadMs only), voxelize, density,
  // fine fills and their total; hierarchy and surface are each session's (0 here).
  const SetupTimings& setupTimings() const { return setup_; }

 private:
  BoneModel() = default;
  // forSession: refuse a bone with no voxel inside, or past this machine's memory for a session.
  static std::shared_ptr<BoneModel> build(geometry::TriangleMesh meshMm, double voxelSizeMm,
                                          const std::string& name, double loadScaleToMm,
                                          const geometry::VoxelizeOptions& voxelizing,
                                          bool sampleFineFills, bool forSession = true);
  static std::shared_ptr<BoneModel> wrapGrid(geometry::VoxelGrid grid, const std::string& name,
                                             double loadMs);
  std::string name_;
  SetupTimings setup_;
  std::optional<geometry::TriangleMesh> mesh_;
  geometry::VoxelGrid grid_;
  std::unique_ptr<geometry::FineFillSource> fineFills_;
  mutable std::once_flag surfaceOnce_;
  mutable std::optional<geometry::TriangleMesh> surfaceMesh_;  // bones without a mesh
  mutable std::once_flag headOnce_;
  mutable std::string headError_;  // why the fit failed, when it did
  mutable std::optional<HumeralHead> head_;
  std::optional<glm::dvec3> up_;
};

// What changed in the surface since the last Session::takeSurfaceChanges() (surface_updater.h).
using SurfaceChanges = geometry::SurfaceDelta;

class Session {
 public:
  // Drills a fresh copy of `bone` (options.voxelSizeMm and voxelizing are the bone's own).
  Session(std::shared_ptr<const BoneModel> bone, const SessionOptions& options);
  // Convenience: the bone made from a mesh, a mesh argument (BoneModel::open) or a grid, then
  // the session.
  static Session fromMesh(geometry::TriangleMesh meshMm, const SessionOptions& options,
                          const std::string& name = "mesh", double loadScaleToMm = 1.0);
  static Session open(const std::string& meshArgument, double scaleToMm,
                      const SessionOptions& options);
  static Session fromGrid(geometry::VoxelGrid grid, const SessionOptions& options,
                          const std::string& name = "grid", double loadMs = 0.0);

  Session(Session&&) noexcept;
  Session& operator=(Session&&) noexcept;
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // ---- each 1 ms step (deterministic mode) ----
  // Refine, force, removal (drilling.h); then the surface follows the changed bricks when
  // keepSurface (the visual work, done here every surfaceEverySteps steps).
  StepOutput step(const StepInput& input);
  // The same step as the device sees it: the proxy (under proxy coupling), the commanded pose
  // and the force to send. step() is this step's simulation output.
  HapticStep hapticStep(const StepInput& input);
  int surfaceEverySteps = 1;

  // A whole path in the deterministic mode (runner.h), one step() after another from t = 0 to
  // its end, or until SIGINT/SIGTERM is recorded (core/interrupt.h: the caller then throws
  // Interrupted): the same input, the same log bit for bit.
  RunResult run(const DrillPath& path, const DeterministicOptions& options = {});
  // The haptic, collision and visual threads in real time for options.durationS (runtime.h): a
  // LiveRuntime (live.h) with a visual thread of its own. Afterwards the session's surface is
  // the visual thread's.
  RuntimeResult runThreaded(PoseSource& source, ForceSink* sink, const RuntimeOptions& options);

  // ---- each frame ----
  // The surface as the visual work left it (the level-0 crack-free surface).
  const geometry::SurfaceMesh& surface();
  // What changed since the last call (everything on the first). Calling it on a session that
  // keeps no surface is a programming error: std::logic_error.
  SurfaceChanges takeSurfaceChanges();
  // Extracts the surface again from the grid as it is now (a full extraction; the changes
  // start over with everything). keepSurface sessions only (else std::logic_error).
  void resetSurface();
  // Frees the kept surface (the incremental updater and the last mesh), for the memory a final
  // extraction needs; surface() then extracts from the grid, and resetSurface() keeps one again.
  void releaseSurface();
  // The drilled bone with its refined regions at their own resolution (for export).
  geometry::SurfaceMesh multiResolutionSurface() const;
  // Tool pose (the proxy's) and the force sent (contact, or coupling and contact) of the
  // latest step.
  const ToolPose& toolPose() const { return lastPose_; }
  const ContactForce& contact() const { return lastContact_; }
  // Per-voxel display values: the finest level present (0, -1, -2; 1 where there is no bone)
  // and the drilling density.
  int levelAt(const glm::ivec3& voxel) const;
  geometry::Density densityAt(const glm::ivec3& voxel) const;

  // ---- what it is built on ----
  const BoneModel& bone() const;
  const std::string& name() const { return bone().name(); }
  const geometry::VoxelGrid& grid() const;
  const geometry::DynamicProximityHierarchy& hierarchy() const;
  DrillingSimulation& simulation();
  const DrillingSimulation& simulation() const;
  // The heat model under the calibrated force model (thermal.h), null otherwise.
  ThermalModel* thermal();
  const ThermalModel* thermal() const;
  // The proxy coupling every run of this session steps through; null under direct coupling.
  ProxyCoupling* coupling();
  const SessionOptions& options() const;
  // Set-up, stage by stage: the bone's stages (shared by every session drilling it) and this
  // session's hierarchy and surface; totalMs is the bone's total plus this session's construction
  // (the first surface is extracted beside the first steps: surfaceMs and surfaceReadyMs are
  // set once it is there).
  const SetupTimings& setupTimings() const;
  // What it holds, by structure (waits for the first surface when it is still being made).
  SessionMemory memory();
  const DrillingTotals& totals() const { return simulation().totals(); }
  double removedVolumeMm3() const { return simulation().removedVolumeMm3(); }
  // The bone's humeral head (fitted once, to the mesh or the grid's surface). Throws InputError
  // for a bone without a head.
  const HumeralHead& humeralHead() const;
  // The seed's portal paths (section 4) on this bone's humeral head, for this session's tool,
  // entering BoneModel::headMesh(). Throws InputError for a bone without a head.
  PortalPlan portalPath(Portal portal, const PortalPathOptions& options = {}) const;

 private:
  // The one step every path takes (step(), hapticStep(), run()): the coupling (null: direct)
  // and the simulation, timed into stepNs; then, with followSurface, the kept surface follows
  // the bricks the step changed, timed into surfaceNs. Either may be null.
  HapticStep advance(const StepInput& input, ProxyCoupling* coupling, bool followSurface,
                     Durations* stepNs, Durations* surfaceNs);
  struct State;
  explicit Session(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
  ToolPose lastPose_;
  ContactForce lastContact_;
};

}  // namespace osteon::simulation
