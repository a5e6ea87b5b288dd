// osteon_bench_drilling's motions: tilts, sweeps, pushes, tremor, through either coupling.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <time.h>
#include <vector>

#include <glm/vec3.hpp>

#include "drilling_bench.h"
#include "osteon/simulation/experiment.h"
#include "osteon/simulation/motions.h"
#include "osteon/simulation/runner.h"

namespace osteon::bench {

using namespace osteon::simulation;

namespace {

struct Config {
  const char* name;
  const std::shared_ptr<const BoneModel>* bone;
  int levels;
};

// Runs one motion under each coupling and case asked for, times its steps and prints its row.
class MotionRunner {
 public:
  MotionRunner(const BenchOptions& o, const std::shared_ptr<const BoneModel>& bone12,
               const std::shared_ptr<const BoneModel>& bone03)
      : o_(o),
        configs_{{"static 0.3 mm", &bone03, 0},
                 {"static 1.2 mm", &bone12, 0},
                 {"dynamic 1.2 mm / 2", &bone12, 2}} {
    cpuUs_.reserve(8000);
    wallUs_.reserve(8000);
  }

  // Every run: a fresh session per coupling and case, the path made on it.
  template <typename MakePath, typename Name>
  void each(const char* family, ToolKind tool, MakePath&& makePath, Name&& name) {
    if (o_.motionSet != "all" && o_.motionSet != family) return;
    for (const CouplingMode coupling : o_.couplings) {
      for (const Config& c : configs_) {
        if (o_.dynamicOnly && c.levels == 0) continue;
        double phaseJitterN = 0.0;
        for (int k = 1; k < o_.phases; ++k) {
          Session session = makeSession(o_, *c.bone, c.levels, coupling, tool);
          std::vector<Waypoint> points = makePath(session).points();
          for (Waypoint& w : points) w.tipMm += glm::dvec3(0.3 * double(k) / double(o_.phases));
          phaseJitterN += run(session, DrillPath(std::move(points))).summary.jitterN;
        }
        for (int k = 0; k < o_.repeats; ++k) {
          Session session = makeSession(o_, *c.bone, c.levels, coupling, tool);
          const RunResult r = run(session, makePath(session));
          if (k == 0) leastUs_ = wallUs_;
          for (std::size_t i = 0; i < leastUs_.size() && i < wallUs_.size(); ++i)
            leastUs_[i] = std::min(leastUs_[i], wallUs_[i]);
          if (k + 1 < o_.repeats) continue;
          report(name(), c, session, r, (phaseJitterN + r.summary.jitterN) / double(o_.phases));
          if (!o_.logDir.empty())
            writeLog(name() + ", " + c.name + ", " + couplingModeName(coupling), r);
        }
      }
    }
  }

 private:
  // The thread's CPU time from one step's end to the next (the step and the runner's few
  // bookkeeping lines): on a shared machine the wall-clock p99 counts the 4 ms slices the
  // scheduler gives to others; this does not. And the wall-clock time between the same two
  // points, per step, for the least over repeats.
  RunResult run(Session& session, const DrillPath& path) {
    cpuUs_.clear();
    wallUs_.clear();
    DeterministicOptions runOptions;
    timespec last{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &last);
    auto lastWall = std::chrono::steady_clock::now();
    runOptions.afterStep = [&](std::size_t, const StepInput&, const StepOutput&) {
      timespec now{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
      const auto nowWall = std::chrono::steady_clock::now();
      cpuUs_.push_back(double(now.tv_sec - last.tv_sec) * 1e6 +
                       double(now.tv_nsec - last.tv_nsec) * 1e-3);
      wallUs_.push_back(std::chrono::duration<double, std::micro>(nowWall - lastWall).count());
      last = now;
      lastWall = nowWall;
    };
    return session.run(path, runOptions);
  }

  void report(const std::string& motion, const Config& c, Session& session, const RunResult& r,
              double phaseJitterN) const {
    const RunSummary& s = r.summary;
    const Percentiles cpu = percentilesOf(cpuUs_);
    const Percentiles least = percentilesOf(leastUs_);
    std::printf(
        "| %s | %s | %s | %.3f | %.4f | %.1f | %.1f | %.1f | %.1f / %.1f / %.1f | %.1f / %.1f | "
        "%.4f | %.3f | %llu | "
        "%llu / %llu | %llu | %zu | %.1f |\n",
        motion.c_str(), couplingModeName(s.coupling), c.name, s.maxStepChangeN, s.jitterN,
        s.hapticStepUs.p50, s.hapticStepUs.p99, s.hapticStepUs.max, cpu.p50, cpu.p99, cpu.max,
        least.p99, least.max, phaseJitterN, s.maxGapMm, (unsigned long long)s.clampSteps,
        (unsigned long long)s.totals.stepsDeferred, (unsigned long long)s.totals.voxelsDeferred,
        (unsigned long long)s.totals.refinePoolExhausted,
        session.simulation().voxels().refinedCount(), s.removedVolumeMm3);
    std::fflush(stdout);
  }

  void writeLog(std::string file, const RunResult& r) const {
    for (char& ch : file) ch = std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' ? ch : '_';
    writeForceLog(r.log, o_.logDir + "/" + file + ".csv",
                  r.summary.coupling == CouplingMode::Proxy);
  }

  const BenchOptions& o_;
  const Config configs_[3];
  std::vector<double> cpuUs_, wallUs_, leastUs_;
};

double loadAverage(double load[3]) {
  if (getloadavg(load, 3) < 0) load[0] = -1.0;
  return load[0];
}

}  // namespace

// The motions a hand makes beyond the seed's straight paths (motions.h), each at static
// 0.3 mm, static 1.2 mm and dynamic 1.2 mm / 2 levels: a tilt sweep of 0-75 degrees on both
// portals, a lateral shaving sweep with each tool, a push into intact bone with the drill off
// then on, a hand's tremor on the portal paths, fast pushes and jumps; each under the couplings
// asked for. Per run, of the force sent to the device: the largest 1 ms change of |F|, the
// jitter; the step's (coupling + drilling) p99 and max; the largest proxy-to-command gap, the
// steps at the clamp, and the shell refinement the budget spread over later steps (steps,
// voxel-steps).
void motions(const BenchOptions& o, const std::shared_ptr<const BoneModel>& bone12,
             const std::shared_ptr<const BoneModel>& bone03) {
  const std::vector<double>& tilts = o.tilts;
  double load[3] = {0, 0, 0};
  loadAverage(load);
  std::printf(
      "\nmotions (deterministic, one thread), built-in humerus; load average at start %.2f %.2f "
      "%.2f\n",
      load[0], load[1], load[2]);
  std::printf(
      "| motion | coupling | case | max 1 ms step N | jitter N | p50 us | p99 us | max us | CPU "
      "p50 / p99 / max us | own p99 / max us (least of %d runs) | jitter N, mean of %d phases | "
      "largest gap mm | steps at clamp | deferred steps / voxel-steps | pool full | refined at end "
      "| removed mm3 |\n",
      o.repeats, o.phases);
  std::printf(
      "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  MotionRunner runner(o, bone12, bone03);
  for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
    for (const double tilt : tilts) {
      PortalPathOptions po;
      po.tiltDeg = tilt;
      runner.each(
          "tilt", ToolKind::Drill, [&](Session& s) { return s.portalPath(portal, po).path; },
          [&] { return std::string(portalName(portal)) + " tilt " + std::to_string(int(tilt)); });
    }
  }
  for (const ToolKind tool : {ToolKind::Drill, ToolKind::Burr, ToolKind::Shaver}) {
    runner.each(
        "lateral", tool,
        [&](Session& s) { return lateralSweepPath(s.portalPath(Portal::FiveOClock)); },
        [&] { return std::string("lateral sweep, ") + toolKindName(tool); });
  }
  // Into intact bone at portal 5's entry, 10 mm past the surface, the drill off 5 s then on 2 s.
  runner.each(
      "push", ToolKind::Drill,
      [&](Session& s) { return intactPushPath(s.portalPath(Portal::FiveOClock)); },
      [] { return std::string("push, drill off 5 s then on 2 s"); });
  // A hand's tremor (1-9 Hz, 0.3 mm, 3 degrees) on both portal paths.
  for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
    runner.each(
        "tremor", ToolKind::Drill,
        [&](Session& s) { return tremorPath(s.portalPath(portal).path); },
        [&] { return std::string("tremor on ") + portalName(portal); });
  }
  // Pushed fast along the portal, the tool upright and tilted both ways: the shaft meets new
  // bone along its length at once, more than one step's refinement budget.
  // And in one step (a device's pose jumping): the most new bone a step can meet, which the
  // refinement budget spreads over the following steps.
  for (const double pushS : {0.1, 0.001}) {
    for (const double tilt : {0.0, 60.0, -40.0}) {
      PortalPathOptions po;
      po.tiltDeg = tilt;
      FastPushOptions fo;
      fo.pushS = pushS;
      runner.each(
          "fast", ToolKind::Drill,
          [&](Session& s) { return fastPushPath(s.portalPath(Portal::FiveOClock, po), fo); },
          [&] {
            char name[96];
            std::snprintf(name, sizeof name, "%s (6 mm in %g ms), tilt %d",
                          pushS < 0.01 ? "jump" : "fast push", pushS * 1000.0, int(tilt));
            return std::string(name);
          });
    }
  }
  loadAverage(load);
  std::printf("load average at end %.2f %.2f %.2f\n", load[0], load[1], load[2]);
}

}  // namespace osteon::bench
