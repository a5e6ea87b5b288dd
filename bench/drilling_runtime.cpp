// osteon_bench_drilling's threaded runtime: 60 s on a path that keeps cutting new bone, against
// the machine's floor measured beside it and after it.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <vector>

#include <glm/geometric.hpp>

#include "drilling_bench.h"
#include "drilling_machine.h"
#include "osteon/simulation/path.h"
#include "osteon/simulation/runtime.h"

namespace osteon::bench {

using namespace osteon::simulation;

namespace {

// One case's sums over the rounds.
struct Totals {
  std::uint64_t periods = 0, overruns = 0, probePeriods = 0, probeOverruns = 0, minutesMet = 0,
                runs = 0;
  double stealS = 0.0;
};

// A helix inside the head, its turns 3.4 mm apart along the head axis: every turn cuts new
// bone, so removal and remeshing never stop.
DrillPath helixPath(const HumeralHead& head, const glm::dvec3& headAxis, double durationS) {
  std::vector<Waypoint> points;
  const glm::dvec3 w = glm::normalize(headAxis);
  const glm::dvec3 u = glm::normalize(
      glm::cross(w, std::abs(w.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 v = glm::cross(w, u);
  const double radiusMm = 8.0, speedMmPerS = 3.0;
  const double omega = speedMmPerS / radiusMm;
  const double pitchPerS = 3.4 * omega / (2.0 * M_PI);
  for (double t = 0.0; t <= durationS + 1e-9; t += 0.05) {
    const glm::dvec3 p = head.centreMm +
                         radiusMm * (std::cos(omega * t) * u + std::sin(omega * t) * v) +
                         (-8.0 + pitchPerS * t) * w;
    const glm::dvec3 tangent =
        -radiusMm * omega * std::sin(omega * t) * u + radiusMm * omega * std::cos(omega * t) * v;
    points.push_back({t, p, ToolPose::pointing(p, tangent).orientation, true});
  }
  return DrillPath(points);
}

// One threaded run's figures beside the probe that ran in the same window.
void printRun(const RuntimeResult& r, const ProbeLoop& probe, double stealS, double runtimeS,
              double voxelMm, int levels, const char* startText) {
  const RuntimeStats& st = r.stats;
  std::printf("threaded runtime, %g s at %g mm / %d levels, helix through the head (started %s)\n",
              runtimeS, voxelMm, levels, startText);
  std::printf("realtime priority: %s\n",
              st.realtimeGranted ? "SCHED_FIFO granted" : "not granted (normal scheduling)");
  if (st.standbyCpu >= 0) {
    std::printf("haptic standby: on (CPUs %d and %d), ran %llu periods\n", st.hapticCpu,
                st.standbyCpu, (unsigned long long)st.standbySteps);
  } else {
    std::printf("haptic standby: off\n");
  }
  const double hapticPct = percentOf(st.hapticOverruns, st.hapticSteps);
  const double probePct = percentOf(probe.overruns(), probe.periods());
  std::printf("haptic: %llu periods, %llu overran (%.4f %%), loop p99 %.1f us\n",
              (unsigned long long)st.hapticSteps, (unsigned long long)st.hapticOverruns, hapticPct,
              st.hapticStepUs.p99);
  std::printf(
      "collision: %llu periods, %llu overran (%.4f %%), step p50 %.1f p99 %.1f max %.1f us\n",
      (unsigned long long)st.collisionSteps, (unsigned long long)st.collisionOverruns,
      percentOf(st.collisionOverruns, st.collisionSteps), st.collisionStepUs.p50,
      st.collisionStepUs.p99, st.collisionStepUs.max);
  std::printf(
      "visual: %llu updates, remesh p50 %.3f p99 %.3f max %.3f ms; bricks handed over %llu, "
      "ring full %llu\n",
      (unsigned long long)st.visualUpdates, st.remeshMs.p50, st.remeshMs.p99, st.remeshMs.max,
      (unsigned long long)st.bricksHandedOver, (unsigned long long)st.ringFull);
  std::printf("removed %.1f mm3, jitter %.4f N\n", r.run.summary.removedVolumeMm3,
              r.run.summary.jitterN);
  std::printf("CPU time stolen by the hypervisor during the run: %.2f s\n", stealS);
  std::printf(
      "floor in the same window (a no-work loop at the haptic priority beside the run): %llu "
      "periods, %llu "
      "overran (%.4f %%); haptic minus floor %+.4f points: %s\n",
      (unsigned long long)probe.periods(), (unsigned long long)probe.overruns(), probePct,
      hapticPct - probePct,
      hapticPct <= probePct + 0.01 ? "within 0.01 (met)" : "over 0.01 (not met)");
  const std::vector<std::int64_t> probeAt = probe.overrunNs();
  std::printf(
      "overruns within 2 ms of a probe overrun: haptic %zu of %zu, collision %zu of %zu; "
      "haptic within 2 ms of a collision overrun: %zu\n",
      coincident(st.hapticOverrunNs, probeAt), st.hapticOverrunNs.size(),
      coincident(st.collisionOverrunNs, probeAt), st.collisionOverrunNs.size(),
      coincident(st.hapticOverrunNs, st.collisionOverrunNs));
  std::fflush(stdout);
}

// The rounds' sums: haptic overruns against the same-window probe's, per case.
void printRounds(const Totals (&totals)[2][2], int rounds, double runtimeS) {
  std::printf("\n%d rounds of %g s, summed: haptic overruns against the same-window probe's\n",
              rounds, runtimeS);
  std::printf(
      "| case | standby | haptic overran | probe overran | haptic - probe | runs within 0.01 | "
      "stolen s |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|\n");
  for (int c = 0; c < 2; ++c) {
    for (int m = 0; m < 2; ++m) {
      const Totals& t = totals[c][m];
      if (t.runs == 0) continue;
      const double h = percentOf(t.overruns, t.periods);
      const double f = percentOf(t.probeOverruns, t.probePeriods);
      std::printf(
          "| %s | %s | %llu of %llu (%.4f %%) | %llu of %llu (%.4f %%) | %+.4f pp | %llu of %llu | "
          "%.2f |\n",
          c == 0 ? "1.2 mm, 2 levels" : "0.3 mm static", m == 1 ? "on" : "off",
          (unsigned long long)t.overruns, (unsigned long long)t.periods, h,
          (unsigned long long)t.probeOverruns, (unsigned long long)t.probePeriods, f, h - f,
          (unsigned long long)t.minutesMet, (unsigned long long)t.runs, t.stealS);
    }
  }
}

}  // namespace

void threadedRuntime(const BenchOptions& o, const std::shared_ptr<const BoneModel>& bone12,
                     const std::shared_ptr<const BoneModel>& bone03, const glm::dvec3& headAxis) {
  const HumeralHead head = bone12->humeralHead();
  const DrillPath path = helixPath(head, headAxis, o.runtimeS);
  Totals totals[2][2];  // [case][standby off, on]
  for (int round = 0; round < o.rounds; ++round) {
    if (o.rounds > 1) std::printf("\nround %d of %d\n", round + 1, o.rounds);
    // The two cases the overrun target names: 1.2 mm with 2 levels, and 0.3 mm static (whose
    // visual thread remeshes 16 times the surface cells).
    for (const auto& [voxelMm, levels] : {std::pair<double, int>{1.2, 2}, {0.3, 0}}) {
      const std::shared_ptr<const BoneModel>& bone = voxelMm == 1.2 ? bone12 : bone03;
      if (round == 0) {
        // The same path in the deterministic mode (one thread, no visual thread): the step's own
        // cost on this path, against which the threaded figures below compare.
        Session alone = makeSession(o, bone, levels);
        const RunSummary s = alone.run(path).summary;
        std::printf(
            "\nhelix path at %g mm / %d levels, deterministic: step p50 %.1f p99 %.1f max %.1f "
            "us\n",
            voxelMm, levels, s.hapticStepUs.p50, s.hapticStepUs.p99, s.hapticStepUs.max);
      }
      for (const bool withStandby : o.standbyModes) {
        Session threaded = makeSession(o, bone, levels);
        PathPoseSource device(path);
        RuntimeOptions ro;
        ro.durationS = o.runtimeS;
        ro.hapticStandby = withStandby;
        char startText[32];
        const std::time_t start =
            std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
        std::strftime(startText, sizeof startText, "%Y-%m-%d %H:%M:%S", std::localtime(&start));
        const double steal0 = stealSeconds();
        ProbeLoop probe(80, std::chrono::microseconds(250));  // the haptic thread's priority
        const RuntimeResult r = threaded.runThreaded(device, nullptr, ro);
        probe.stop();
        const double stealS = stealSeconds() - steal0;
        const RuntimeStats& st = r.stats;
        printRun(r, probe, stealS, o.runtimeS, voxelMm, levels, startText);
        const double hapticPct = percentOf(st.hapticOverruns, st.hapticSteps);
        const double probePct = percentOf(probe.overruns(), probe.periods());
        Totals& t = totals[voxelMm == 1.2 ? 0 : 1][withStandby ? 1 : 0];
        t.periods += st.hapticSteps;
        t.overruns += st.hapticOverruns;
        t.probePeriods += probe.periods();
        t.probeOverruns += probe.overruns();
        t.minutesMet += hapticPct <= probePct + 0.01 ? 1 : 0;
        t.runs += 1;
        t.stealS += stealS;
      }
    }
  }
  if (o.rounds > 1) printRounds(totals, o.rounds, o.runtimeS);
  const OverrunFloor floor = overrunFloor(o.runtimeS);
  std::printf(
      "\nmachine floor, %g s: the same two 1 kHz loops with no work, a thread streaming memory "
      "beside them\n",
      o.runtimeS);
  std::printf(
      "haptic: %llu periods, %llu overran (%.4f %%); collision: %llu periods, %llu overran (%.4f "
      "%%); "
      "stolen %.2f s\n",
      (unsigned long long)floor.periods[0], (unsigned long long)floor.overruns[0],
      percentOf(floor.overruns[0], floor.periods[0]), (unsigned long long)floor.periods[1],
      (unsigned long long)floor.overruns[1], percentOf(floor.overruns[1], floor.periods[1]),
      floor.stealS);
}

}  // namespace osteon::bench
