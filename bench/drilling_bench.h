// The pieces osteon_bench_drilling's parts share (drilling_bench.cpp gives the usage): its
// options, and a session on the built-in humerus made from them.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "osteon/simulation/coupling.h"
#include "osteon/simulation/session.h"

namespace osteon::bench {

struct BenchOptions {
  double runtimeS = 60.0;
  double skin = simulation::DrillingOptions{}.querySkinVoxels;
  std::size_t slices = simulation::DrillingOptions{}.querySliceNodes;
  bool haptic = true;
  bool withMotions = false, motionsOnly = false;
  std::vector<double> tilts = {0, 20, 40, 60, 75, -40, -60};
  std::vector<bool> standbyModes = {true};
  int rounds = 1;
  // --cutting-refine-only: refinement around the cutting parts alone (the seed's), to compare.
  bool refineShells = true;
  bool dynamicOnly = false;  // --dynamic-only: the motions at 1.2 mm / 2 levels alone
  std::size_t refineBudget = simulation::DrillingOptions{}.refineBudgetVoxels;
  std::vector<simulation::CouplingMode> couplings = {simulation::CouplingMode::Proxy,
                                                     simulation::CouplingMode::Direct};
  std::string motionSet = "all";
  // --repeats N: each motion run N times (deterministic: the same work every time); the "own"
  // columns give each step's least time over the N runs, what the step costs without the time
  // a shared machine takes from it now and then.
  int repeats = 1;
  // --phases N: each motion also run with its path shifted by k/N of a 0.3 mm sample along each
  // axis (k = 1..N-1): the same motion at N phases of the sampling lattice. Held against bone
  // the proxy sticks and slips, and which slips fall in jitter's [2, 5] s window turns on the
  // lattice's phase; the mean over the phases compares two discretizations, one run does not.
  int phases = 1;
  std::string logDir;  // --log-dir D: each motion's force log, D/<motion>, <case>, <coupling>.csv
};

// A session on the built-in humerus; sessions of one voxel size share their bone.
inline simulation::Session makeSession(
    const BenchOptions& o, const std::shared_ptr<const simulation::BoneModel>& bone, int levels,
    simulation::CouplingMode coupling = simulation::CouplingMode::Direct,
    simulation::ToolKind tool = simulation::ToolKind::Drill) {
  simulation::SessionOptions options;
  options.levels = levels;
  options.coupling = coupling;
  options.tool = tool;
  options.drilling.querySkinVoxels = o.skin;
  options.drilling.querySliceNodes = o.slices;
  options.drilling.refineShells = o.refineShells;
  options.drilling.refineBudgetVoxels = o.refineBudget;
  options.keepSurface = false;  // the haptic step alone; the runtime keeps its own surface
  return simulation::Session(bone, options);
}

// The motions a hand makes (drilling_motions.cpp).
void motions(const BenchOptions& o, const std::shared_ptr<const simulation::BoneModel>& bone12,
             const std::shared_ptr<const simulation::BoneModel>& bone03);

// The threaded runtime on a helix through the head, then the machine's floor
// (drilling_runtime.cpp).
void threadedRuntime(const BenchOptions& o,
                     const std::shared_ptr<const simulation::BoneModel>& bone12,
                     const std::shared_ptr<const simulation::BoneModel>& bone03,
                     const glm::dvec3& headAxis);

}  // namespace osteon::bench
