// osteon_bench_drilling [--runtime-s S] [--runtime-only] [--floor-only S] [--query-skin VOXELS]
//                       [--motions | --motions-only] [--tilts DEG,DEG...] [--cutting-refine-only]
//                       [--refine-budget VOXELS] [--dynamic-only]
//                       [--query-slice NODES] [--standby on|off|both] [--repeat N]
//                       [--cpu-stalls S] [--coupling proxy|direct|both]
//                       [--motion-set tilt|lateral|push|tremor|fast|all] [--repeats N] [--phases N]
//                       [--log-dir D]:
// the drilling figures of
// docs/performance.md.
//   1. Haptic step (refinement + contact force + removal) on both portals of the built-in
//      humerus at 1.2 mm with 2 levels and at 0.3 mm static, deterministic mode: p50/p99/max,
//      and the force jitter of each (dynamic 1.2 mm must be no worse than static 0.3 mm).
//      Beside them, the machine's own noise: a fixed workload's p50, p99 and max.
//   2. The threaded runtime for S seconds (default 60) at 1.2 mm with 2 levels and at 0.3 mm
//      static, each on a path that keeps cutting new bone, so the visual thread is always
//      remeshing: the share of 1 ms periods that overran, the
//      CPU time the hypervisor stole meanwhile, and the floor of that same window (a no-work
//      loop at the haptic priority running beside the run); then the machine's floor alone:
//      the same loops with no work for S seconds. --standby both runs each case twice, the
//      haptic loop without its standby thread, then with it (runtime.h). --repeat N runs
//      the cases N times in turn and sums each case's overruns against its probes': one
//      minute's difference is within the minute-to-minute spread, N minutes' is not.
//   3. --cpu-stalls S alone: a no-work loop pinned to each CPU for S seconds, and how many of
//      one CPU's overruns another CPU shares.
//   4. --motions (before 1.; --motions-only alone; --tilts 40,60 picks the tilts): the motions a
//      hand makes (motions.h), each at static 0.3 mm, static 1.2 mm and dynamic 1.2 mm / 2:
//      max 1 ms step, jitter, step p99 and max, steps at the clamp, refinement deferred.
//      --cutting-refine-only refines around the cutting parts alone (as the seed), to compare;
//      --refine-budget sets DrillingOptions::refineBudgetVoxels (0: no limit).
//      --coupling (default both) runs each motion through the proxy coupling, directly (the
//      tool where the path puts it), or both; either way through stepHaptic, the one haptic
//      step every run mode takes, and the step time is the coupling's and the drilling's.
//      --motion-set picks one family: tilt sweeps, lateral sweeps, the push into intact bone
//      (drill off 5 s, then on), the tremor path, or the fast pushes and jumps. --repeats N
//      runs each motion N times and adds each step's least wall-clock time over them;
//      --phases N adds the mean jitter over N phases of the sampling lattice (gPhases);
//      --log-dir D writes each run's force log there.
#include "drilling_bench.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "drilling_machine.h"
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/experiment.h"
#include "osteon/simulation/session.h"

using namespace osteon;
using namespace osteon::simulation;
using namespace osteon::bench;

namespace {

// Reads the options into `o`; returns -1 to go on, or the exit code of a run that ended here
// (--cpu-stalls, --floor-only) or of a bad option.
int parseOptions(int argc, char** argv, BenchOptions& o) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--query-skin") == 0 && i + 1 < argc) o.skin = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--query-slice") == 0 && i + 1 < argc)
      o.slices = std::size_t(std::atol(argv[i + 1]));
    if (std::strcmp(argv[i], "--runtime-s") == 0 && i + 1 < argc)
      o.runtimeS = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--runtime-only") == 0) o.haptic = false;
    if (std::strcmp(argv[i], "--motions") == 0) o.withMotions = true;
    if (std::strcmp(argv[i], "--cutting-refine-only") == 0) o.refineShells = false;
    if (std::strcmp(argv[i], "--dynamic-only") == 0) o.dynamicOnly = true;
    if (std::strcmp(argv[i], "--refine-budget") == 0 && i + 1 < argc)
      o.refineBudget = std::size_t(std::atol(argv[i + 1]));
    if (std::strcmp(argv[i], "--motions-only") == 0) o.withMotions = o.motionsOnly = true;
    if (std::strcmp(argv[i], "--motion-set") == 0 && i + 1 < argc) o.motionSet = argv[i + 1];
    if (std::strcmp(argv[i], "--phases") == 0 && i + 1 < argc)
      o.phases = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--log-dir") == 0 && i + 1 < argc) o.logDir = argv[i + 1];
    if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc)
      o.repeats = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--coupling") == 0 && i + 1 < argc) {
      const std::string mode = argv[i + 1];
      if (mode == "both") {
        o.couplings = {CouplingMode::Proxy, CouplingMode::Direct};
      } else if (mode == "proxy" || mode == "direct") {
        o.couplings = {parseCouplingMode(mode)};
      } else {
        std::fprintf(stderr, "--coupling %s: not proxy, direct or both\n", mode.c_str());
        return 2;
      }
    }
    if (std::strcmp(argv[i], "--o.tilts") == 0 && i + 1 < argc) {
      // Comma-separated degrees, e.g. 40,60.
      o.tilts.clear();
      for (const char* p = argv[i + 1]; *p;) {
        char* end = nullptr;
        o.tilts.push_back(std::strtod(p, &end));
        if (end == p) break;
        p = *end == ',' ? end + 1 : end;
      }
    }
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      o.rounds = std::atoi(argv[i + 1]);
      if (o.rounds < 1 || o.rounds > 1000) {
        std::fprintf(stderr, "--repeat %s: not a count from 1 to 1000\n", argv[i + 1]);
        return 2;
      }
    }
    if (std::strcmp(argv[i], "--cpu-stalls") == 0 && i + 1 < argc) {
      cpuStalls(std::atof(argv[i + 1]));
      return 0;
    }
    if (std::strcmp(argv[i], "--standby") == 0 && i + 1 < argc) {
      const std::string mode = argv[i + 1];
      if (mode == "off") {
        o.standbyModes = {false};
      } else if (mode == "both") {
        o.standbyModes = {false, true};
      } else if (mode != "on") {
        std::fprintf(stderr, "--standby %s: not on, off or both\n", mode.c_str());
        return 2;
      }
    }
    if (std::strcmp(argv[i], "--floor-only") == 0 && i + 1 < argc) {
      // The machine's floor alone, for a run measured elsewhere (bench/viewer_bench.sh).
      const OverrunFloor floor = overrunFloor(std::atof(argv[i + 1]));
      std::printf("floor %llu %llu %llu %llu %.2f\n", (unsigned long long)floor.periods[0],
                  (unsigned long long)floor.overruns[0], (unsigned long long)floor.periods[1],
                  (unsigned long long)floor.overruns[1], floor.stealS);
      return 0;
    }
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions o;
  if (const int code = parseOptions(argc, argv, o); code >= 0) return code;
  const geometry::HumerusModel model = geometry::buildHumerusModel();
  // The built-in humerus, opened as `drill default` opens it (0.3 mm: static only, no fine fills).
  const auto openDefault = [](double voxelSizeMm, bool fineFills) {
    BoneSource source;
    source.voxelSizeMm = voxelSizeMm;
    source.sampleFineFills = fineFills;
    return BoneModel::open(source).bone;
  };
  const std::shared_ptr<const BoneModel> bone12 = openDefault(1.2, true);
  const std::shared_ptr<const BoneModel> bone03 = openDefault(0.3, false);
  if (o.withMotions) motions(o, bone12, bone03);
  if (o.motionsOnly) return 0;

  if (o.haptic)
    std::printf("haptic step (deterministic, one thread), built-in humerus, 7 s portal paths\n");
  if (o.haptic)
    std::printf("query caches: skin %g base voxels, %zu nodes per slice\n", o.skin, o.slices);
  if (o.haptic)
    std::printf(
        "| base voxel | levels | force voxel | portal | p50 us | p99 us | max us | jitter N | max "
        "step change N | steps that walked |\n");
  if (o.haptic) std::printf("|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& [voxelMm, levels] : {std::pair<double, int>{1.2, 2}, {0.3, 0}}) {
    if (!o.haptic) break;
    for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
      Session session = makeSession(o, voxelMm == 1.2 ? bone12 : bone03, levels);
      const RunResult r = session.run(session.portalPath(portal).path);
      const RunSummary& s = r.summary;
      std::printf("| %g mm | %d | %g mm | %s | %.1f | %.1f | %.1f | %.4f | %.4f | %llu |\n",
                  voxelMm, levels, session.simulation().finestVoxelMm(), portalName(portal),
                  s.hapticStepUs.p50, s.hapticStepUs.p99, s.hapticStepUs.max, s.jitterN,
                  s.maxStepChangeN, (unsigned long long)session.totals().stepsThatWalked);
      std::fflush(stdout);
    }
  }
  if (o.haptic) {
    const Percentiles noise = noiseFloor();
    std::printf(
        "machine noise: a fixed workload timed the same way, p50 %.1f p99 %.1f max %.1f us\n",
        noise.p50, noise.p99, noise.max);
  }

  threadedRuntime(o, bone12, bone03, model.headAxis);
  return 0;
}
