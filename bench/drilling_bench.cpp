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
#include "osteon/geometry/io/humerus_model.h"
#include "osteon/simulation/bone_source.h"
#include "osteon/simulation/experiment.h"
#include "osteon/simulation/motions.h"
#include "osteon/simulation/runtime.h"
#include "osteon/simulation/session.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

using namespace osteon;
using namespace osteon::simulation;

namespace {

// --cutting-refine-only: refinement around the cutting parts alone (the seed's), to compare.
bool gRefineShells = true;
bool gDynamicOnly = false;  // --dynamic-only: the motions at 1.2 mm / 2 levels alone
std::size_t gRefineBudget = DrillingOptions{}.refineBudgetVoxels;
std::vector<CouplingMode> gCouplings = {CouplingMode::Proxy, CouplingMode::Direct};
std::string gMotionSet = "all";
// --repeats N: each motion run N times (deterministic: the same work every time); the "own"
// columns give each step's least time over the N runs, what the step costs without the time
// a shared machine takes from it now and then.
int gRepeats = 1;
// --phases N: each motion also run with its path shifted by k/N of a 0.3 mm sample along each
// axis (k = 1..N-1): the same motion at N phases of the sampling lattice. Held against bone the
// proxy sticks and slips, and which slips fall in jitter's [2, 5] s window turns on the
// lattice's phase; the mean over the phases compares two discretizations, one run does not.
int gPhases = 1;
std::string gLogDir;  // --log-dir D: each motion's force log, D/<motion>, <case>, <coupling>.csv
bool wanted(const char* family) {
  return gMotionSet == "all" || gMotionSet == family;
}

// A session on the built-in humerus; sessions of one voxel size share their bone.
Session makeSession(const std::shared_ptr<const BoneModel>& bone, int levels,
                    double querySkinVoxels = DrillingOptions{}.querySkinVoxels,
                    std::size_t querySliceNodes = DrillingOptions{}.querySliceNodes,
                    CouplingMode coupling = CouplingMode::Direct, ToolKind tool = ToolKind::Drill) {
  SessionOptions options;
  options.levels = levels;
  options.coupling = coupling;
  options.tool = tool;
  options.drilling.querySkinVoxels = querySkinVoxels;
  options.drilling.querySliceNodes = querySliceNodes;
  options.drilling.refineShells = gRefineShells;
  options.drilling.refineBudgetVoxels = gRefineBudget;
  options.keepSurface = false;  // the haptic step alone; the runtime keeps its own surface
  return Session(bone, options);
}

// The machine's own timing noise: a fixed workload, the same every time (about a haptic step's
// median on the development machine, over a 256 KiB array), timed 7,001 times as the runner
// times a step. Its p99 over its p50 is what the machine adds to any step's p99.
Percentiles noiseFloor() {
  std::vector<double> data(32768, 1.0), us;
  us.reserve(7001);
  double sink = 0.0;
  for (int i = 0; i < 7001; ++i) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t j = 0; j < data.size(); j += 3) sink += std::sqrt(data[j] * double(j));
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
  }
  if (sink < 0.0) std::printf("unreachable\n");  // keeps the work
  return percentilesOf(us);
}

// CPU time the hypervisor gave to other guests while this one had work ("steal" in
// /proc/stat), in seconds since boot; -1 where the kernel does not say.
double stealSeconds() {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  unsigned long long user, nice, system, idle, iowait, irq, softirq, steal;
  if (!(stat >> cpu >> user >> nice >> system >> idle >> iowait >> irq >> softirq >> steal) || cpu != "cpu") return -1.0;
  return double(steal) / double(sysconf(_SC_CLK_TCK));
}

// The machine's own overrun floor: the runtime's two 1 kHz loops (SCHED_FIFO, absolute
// deadlines, the same overrun rule) with no work at all, beside a thread streaming through
// 64 MiB as a busy visual thread does. Every overrun here is the machine's.
struct OverrunFloor {
  std::uint64_t periods[2] = {0, 0}, overruns[2] = {0, 0};
  double stealS = 0.0;
};

using Clock = std::chrono::steady_clock;

// A no-work 1 kHz loop at SCHED_FIFO `priority` with the runtime's rule: absolute deadlines
// from `startAt`; a period whose wake-up ends after the period is an overrun (onOverrun gets
// its end), and the periods it missed are skipped. Runs while keepGoing(k); returns the periods.
template <class KeepGoing, class OnOverrun>
std::uint64_t noWorkLoop(int priority, Clock::time_point startAt, KeepGoing&& keepGoing,
                         OnOverrun&& onOverrun) {
  sched_param p{};
  p.sched_priority = priority;
  pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
  const auto period = std::chrono::milliseconds(1);
  std::uint64_t periods = 0;
  for (std::uint64_t k = 0; keepGoing(k);) {
    const auto deadline = startAt + k * period;
    std::this_thread::sleep_until(deadline);
    const auto end = Clock::now();
    ++periods;
    if (end > deadline + period) {
      onOverrun(end);
      k = std::uint64_t((end - startAt) / period) + 1;
    } else {
      ++k;
    }
  }
  return periods;
}

// A no-work 1 kHz loop (SCHED_FIFO, absolute deadlines, the runtime's overrun rule) running
// beside something else until stopped: the floor of that very window, with the same load,
// the same hypervisor steal and the same memory traffic as what it runs beside.
class ProbeLoop {
 public:
  ProbeLoop(int priority, std::chrono::microseconds offset) {
    overrunNs_.assign(RuntimeStats::kOverrunInstantsKept, 0);
    thread_ = std::thread([this, priority, offset] {
      periods_ = noWorkLoop(
          priority, Clock::now() + offset, [this](std::uint64_t) { return !stop_.load(std::memory_order_relaxed); },
          [this](Clock::time_point end) {
            if (overruns_ < overrunNs_.size()) overrunNs_[overruns_] = end.time_since_epoch().count();
            ++overruns_;
          });
    });
  }
  void stop() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }
  ~ProbeLoop() { stop(); }
  std::uint64_t periods() const { return periods_; }
  std::uint64_t overruns() const { return overruns_; }
  // Steady-clock (CLOCK_MONOTONIC) ns of the first overruns, as RuntimeStats keeps them.
  std::vector<std::int64_t> overrunNs() const {
    return {overrunNs_.begin(), overrunNs_.begin() + std::ptrdiff_t(std::min<std::uint64_t>(overruns_, overrunNs_.size()))};
  }

 private:
  std::vector<std::int64_t> overrunNs_;
  std::atomic<bool> stop_{false};
  std::uint64_t periods_ = 0, overruns_ = 0;
  std::thread thread_;
};

// Overruns of `a` that end within 2 ms of one of `b`'s: the same stall seen by both.
std::size_t coincident(const std::vector<std::int64_t>& a, const std::vector<std::int64_t>& b) {
  std::size_t n = 0;
  for (const std::int64_t t : a) {
    for (const std::int64_t u : b) {
      if (std::llabs(t - u) <= 2000000) {
        ++n;
        break;
      }
    }
  }
  return n;
}

// `part` as a percentage of `whole` (0 when nothing ran).
double percentOf(std::uint64_t part, std::uint64_t whole) {
  return 100.0 * double(part) / double(std::max<std::uint64_t>(whole, 1));
}

OverrunFloor overrunFloor(double seconds) {
  OverrunFloor f;
  std::atomic<bool> stop{false};
  const auto startAt = Clock::now() + std::chrono::milliseconds(5);
  const auto periods = std::uint64_t(seconds * 1000.0);
  const auto loop = [&](int which, int priority, std::chrono::microseconds offset) {
    f.periods[which] = noWorkLoop(
        priority, startAt + offset, [&](std::uint64_t k) { return k < periods; },
        [&](Clock::time_point) { ++f.overruns[which]; });
  };
  const double steal0 = stealSeconds();
  std::thread busy([&] {
    std::vector<double> data(8 << 20, 1.0);
    double sink = 0.0;
    while (!stop.load(std::memory_order_relaxed)) {
      for (std::size_t i = 0; i < data.size(); i += 8) sink += data[i];
    }
    if (sink < 0.0) std::printf("unreachable\n");
  });
  std::thread haptic(loop, 0, 80, std::chrono::microseconds(0));
  std::thread collision(loop, 1, 79, std::chrono::microseconds(500));
  haptic.join();
  collision.join();
  stop.store(true);
  busy.join();
  f.stealS = stealSeconds() - steal0;
  return f;
}

// Where the machine's stalls land: one no-work 1 kHz loop pinned to each CPU (SCHED_FIFO 80,
// staggered), for `seconds`. Prints each CPU's overruns and how many of them fall within 2 ms
// of another CPU's: the case for the haptic loop's standby thread on a second CPU (runtime.h).
void cpuStalls(double seconds) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  sched_getaffinity(0, sizeof allowed, &allowed);
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &allowed)) cpus.push_back(c);
  }
  std::vector<std::vector<std::int64_t>> at(cpus.size());
  const auto startAt = Clock::now() + std::chrono::milliseconds(5);
  const auto periods = std::uint64_t(seconds * 1000.0);
  std::vector<std::thread> loops;
  const double steal0 = stealSeconds();
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    loops.emplace_back([&, i] {
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpus[i], &one);
      pthread_setaffinity_np(pthread_self(), sizeof one, &one);
      at[i].reserve(RuntimeStats::kOverrunInstantsKept);
      const auto offset = std::chrono::microseconds(1000 * std::int64_t(i) / std::int64_t(cpus.size()));
      noWorkLoop(
          80, startAt + offset, [&](std::uint64_t k) { return k < periods; },
          [&, i](Clock::time_point end) {
            if (at[i].size() < at[i].capacity()) at[i].push_back(end.time_since_epoch().count());
          });
    });
  }
  for (std::thread& t : loops) t.join();
  std::printf("no-work 1 kHz loops pinned one per CPU, %g s, stolen %.2f s:\n", seconds, stealSeconds() - steal0);
  for (std::size_t i = 0; i < cpus.size(); ++i) {
    std::vector<std::int64_t> others;
    for (std::size_t j = 0; j < cpus.size(); ++j) {
      if (j != i) others.insert(others.end(), at[j].begin(), at[j].end());
    }
    std::printf("  CPU %d: %zu overran, %zu of them within 2 ms of another CPU's\n", cpus[i], at[i].size(),
                coincident(at[i], others));
  }
}

// The motions a hand makes beyond the seed's straight paths (motions.h), each at static
// 0.3 mm, static 1.2 mm and dynamic 1.2 mm / 2 levels: a tilt sweep of 0-75 degrees on both
// portals, a lateral shaving sweep with each tool, a push into intact bone with the drill off
// then on, a hand's tremor on the portal paths, fast pushes and jumps; each under the couplings
// asked for. Per run, of the force sent to the device: the largest 1 ms change of |F|, the
// jitter; the step's (coupling + drilling) p99 and max; the largest proxy-to-command gap, the
// steps at the clamp, and the shell refinement the budget spread over later steps (steps,
// voxel-steps).
void motions(const std::shared_ptr<const BoneModel>& bone12, const std::shared_ptr<const BoneModel>& bone03,
             const std::vector<double>& tilts) {
  struct Config {
    const char* name;
    const std::shared_ptr<const BoneModel>* bone;
    int levels;
  };
  const Config configs[] = {{"static 0.3 mm", &bone03, 0}, {"static 1.2 mm", &bone12, 0}, {"dynamic 1.2 mm / 2", &bone12, 2}};
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = -1.0;
  std::printf("\nmotions (deterministic, one thread), built-in humerus; load average at start %.2f %.2f %.2f\n", load[0],
              load[1], load[2]);
  std::printf(
      "| motion | coupling | case | max 1 ms step N | jitter N | p50 us | p99 us | max us | CPU "
      "p50 / p99 / max us | own p99 / max us (least of %d runs) | jitter N, mean of %d phases | "
      "largest gap mm | steps at clamp | deferred steps / voxel-steps | pool full | refined at end "
      "| removed mm3 |\n",
      gRepeats, gPhases);
  std::printf("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  // The thread's CPU time from one step's end to the next (the step and the runner's few
  // bookkeeping lines): on a shared machine the wall-clock p99 counts the 4 ms slices the
  // scheduler gives to others; this does not.
  // And the wall-clock time between the same two points, per step, for the least over repeats.
  std::vector<double> cpuUs, wallUs, leastUs;
  cpuUs.reserve(8000);
  wallUs.reserve(8000);
  const auto run = [&cpuUs, &wallUs](Session& session, const DrillPath& path) {
    cpuUs.clear();
    wallUs.clear();
    DeterministicOptions o;
    timespec last{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &last);
    auto lastWall = std::chrono::steady_clock::now();
    o.afterStep = [&](std::size_t, const StepInput&, const StepOutput&) {
      timespec now{};
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
      const auto nowWall = std::chrono::steady_clock::now();
      cpuUs.push_back(double(now.tv_sec - last.tv_sec) * 1e6 + double(now.tv_nsec - last.tv_nsec) * 1e-3);
      wallUs.push_back(std::chrono::duration<double, std::micro>(nowWall - lastWall).count());
      last = now;
      lastWall = nowWall;
    };
    return session.run(path, o);
  };
  double phaseJitterN = 0.0;
  const auto report = [&cpuUs, &leastUs, &phaseJitterN](const std::string& motion, const Config& c,
                                                        Session& session, const RunResult& r) {
    const RunSummary& s = r.summary;
    const Percentiles cpu = percentilesOf(cpuUs);
    const Percentiles least = percentilesOf(leastUs);
    std::printf(
        "| %s | %s | %s | %.3f | %.4f | %.1f | %.1f | %.1f | %.1f / %.1f / %.1f | %.1f / %.1f | %.4f | %.3f | %llu | "
        "%llu / %llu | %llu | %zu | %.1f |\n",
        motion.c_str(), couplingModeName(s.coupling), c.name, s.maxStepChangeN, s.jitterN,
        s.hapticStepUs.p50, s.hapticStepUs.p99, s.hapticStepUs.max, cpu.p50, cpu.p99, cpu.max, least.p99, least.max,
        phaseJitterN,
        s.maxGapMm, (unsigned long long)s.clampSteps, (unsigned long long)s.totals.stepsDeferred,
        (unsigned long long)s.totals.voxelsDeferred,
        (unsigned long long)s.totals.refinePoolExhausted,
        session.simulation().voxels().refinedCount(), s.removedVolumeMm3);
    std::fflush(stdout);
  };
  // Every run: a fresh session per coupling and case, the path made on it.
  const auto each = [&](const char* family, ToolKind tool, auto&& makePath, auto&& name) {
    if (!wanted(family)) return;
    for (const CouplingMode coupling : gCouplings) {
      for (const Config& c : configs) {
        if (gDynamicOnly && c.levels == 0) continue;
        phaseJitterN = 0.0;
        for (int k = 1; k < gPhases; ++k) {
          Session session = makeSession(*c.bone, c.levels, DrillingOptions{}.querySkinVoxels,
                                        DrillingOptions{}.querySliceNodes, coupling, tool);
          std::vector<Waypoint> points = makePath(session).points();
          for (Waypoint& w : points) w.tipMm += glm::dvec3(0.3 * double(k) / double(gPhases));
          phaseJitterN += run(session, DrillPath(std::move(points))).summary.jitterN;
        }
        for (int k = 0; k < gRepeats; ++k) {
          Session session = makeSession(*c.bone, c.levels, DrillingOptions{}.querySkinVoxels,
                                        DrillingOptions{}.querySliceNodes, coupling, tool);
          const DrillPath path = makePath(session);
          const RunResult r = run(session, path);
          if (k == 0) leastUs = wallUs;
          for (std::size_t i = 0; i < leastUs.size() && i < wallUs.size(); ++i)
            leastUs[i] = std::min(leastUs[i], wallUs[i]);
          if (k + 1 == gRepeats) {
            phaseJitterN = (phaseJitterN + r.summary.jitterN) / double(gPhases);
            report(name(), c, session, r);
          }
          if (k + 1 == gRepeats && !gLogDir.empty()) {
            std::string file = name() + ", " + c.name + ", " + couplingModeName(coupling);
            for (char& ch : file) ch = std::isalnum((unsigned char)ch) || ch == '-' ? ch : '_';
            writeForceLog(r.log, gLogDir + "/" + file + ".csv", coupling == CouplingMode::Proxy);
          }
        }
      }
    }
  };
  for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
    for (const double tilt : tilts) {
      PortalPathOptions po;
      po.tiltDeg = tilt;
      each(
          "tilt", ToolKind::Drill, [&](Session& s) { return s.portalPath(portal, po).path; },
          [&] { return std::string(portalName(portal)) + " tilt " + std::to_string(int(tilt)); });
    }
  }
  for (const ToolKind tool : {ToolKind::Drill, ToolKind::Burr, ToolKind::Shaver}) {
    each(
        "lateral", tool,
        [&](Session& s) { return lateralSweepPath(s.portalPath(Portal::FiveOClock)); },
        [&] { return std::string("lateral sweep, ") + toolKindName(tool); });
  }
  // Into intact bone at portal 5's entry, 10 mm past the surface, the drill off 5 s then on 2 s.
  each(
      "push", ToolKind::Drill,
      [&](Session& s) { return intactPushPath(s.portalPath(Portal::FiveOClock)); },
      [] { return std::string("push, drill off 5 s then on 2 s"); });
  // A hand's tremor (1-9 Hz, 0.3 mm, 3 degrees) on both portal paths.
  for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
    each(
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
      each(
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
  if (getloadavg(load, 3) < 0) load[0] = -1.0;
  std::printf("load average at end %.2f %.2f %.2f\n", load[0], load[1], load[2]);
}

}  // namespace

int main(int argc, char** argv) {
  double runtimeS = 60.0;
  double skin = DrillingOptions{}.querySkinVoxels;
  std::size_t slices = DrillingOptions{}.querySliceNodes;
  bool haptic = true;
  bool withMotions = false, motionsOnly = false;
  std::vector<double> tilts = {0, 20, 40, 60, 75, -40, -60};
  std::vector<bool> standbyModes = {true};
  int rounds = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--query-skin") == 0 && i + 1 < argc) skin = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--query-slice") == 0 && i + 1 < argc) slices = std::size_t(std::atol(argv[i + 1]));
    if (std::strcmp(argv[i], "--runtime-s") == 0 && i + 1 < argc) runtimeS = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--runtime-only") == 0) haptic = false;
    if (std::strcmp(argv[i], "--motions") == 0) withMotions = true;
    if (std::strcmp(argv[i], "--cutting-refine-only") == 0) gRefineShells = false;
    if (std::strcmp(argv[i], "--dynamic-only") == 0) gDynamicOnly = true;
    if (std::strcmp(argv[i], "--refine-budget") == 0 && i + 1 < argc) gRefineBudget = std::size_t(std::atol(argv[i + 1]));
    if (std::strcmp(argv[i], "--motions-only") == 0) withMotions = motionsOnly = true;
    if (std::strcmp(argv[i], "--motion-set") == 0 && i + 1 < argc) gMotionSet = argv[i + 1];
    if (std::strcmp(argv[i], "--phases") == 0 && i + 1 < argc) gPhases = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--log-dir") == 0 && i + 1 < argc) gLogDir = argv[i + 1];
    if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) gRepeats = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--coupling") == 0 && i + 1 < argc) {
      const std::string mode = argv[i + 1];
      if (mode == "both") {
        gCouplings = {CouplingMode::Proxy, CouplingMode::Direct};
      } else if (mode == "proxy" || mode == "direct") {
        gCouplings = {parseCouplingMode(mode)};
      } else {
        std::fprintf(stderr, "--coupling %s: not proxy, direct or both\n", mode.c_str());
        return 2;
      }
    }
    if (std::strcmp(argv[i], "--tilts") == 0 && i + 1 < argc) {
      // Comma-separated degrees, e.g. 40,60.
      tilts.clear();
      for (const char* p = argv[i + 1]; *p;) {
        char* end = nullptr;
        tilts.push_back(std::strtod(p, &end));
        if (end == p) break;
        p = *end == ',' ? end + 1 : end;
      }
    }
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      rounds = std::atoi(argv[i + 1]);
      if (rounds < 1 || rounds > 1000) {
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
        standbyModes = {false};
      } else if (mode == "both") {
        standbyModes = {false, true};
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
  const HumeralHead head = bone12->humeralHead();
  if (withMotions) motions(bone12, bone03, tilts);
  if (motionsOnly) return 0;

  if (haptic) std::printf("haptic step (deterministic, one thread), built-in humerus, 7 s portal paths\n");
  if (haptic) std::printf("query caches: skin %g base voxels, %zu nodes per slice\n", skin, slices);
  if (haptic) std::printf("| base voxel | levels | force voxel | portal | p50 us | p99 us | max us | jitter N | max step change N | steps that walked |\n");
  if (haptic) std::printf("|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|\n");
  for (const auto& [voxelMm, levels] : {std::pair<double, int>{1.2, 2}, {0.3, 0}}) {
    if (!haptic) break;
    for (const Portal portal : {Portal::FiveOClock, Portal::SevenOClock}) {
      Session session = makeSession(voxelMm == 1.2 ? bone12 : bone03, levels, skin, slices);
      const RunResult r = session.run(session.portalPath(portal).path);
      const RunSummary& s = r.summary;
      std::printf("| %g mm | %d | %g mm | %s | %.1f | %.1f | %.1f | %.4f | %.4f | %llu |\n", voxelMm, levels,
                  session.simulation().finestVoxelMm(), portalName(portal), s.hapticStepUs.p50, s.hapticStepUs.p99,
                  s.hapticStepUs.max, s.jitterN, s.maxStepChangeN,
                  (unsigned long long)session.totals().stepsThatWalked);
      std::fflush(stdout);
    }
  }
  if (haptic) {
    const Percentiles noise = noiseFloor();
    std::printf("machine noise: a fixed workload timed the same way, p50 %.1f p99 %.1f max %.1f us\n", noise.p50,
                noise.p99, noise.max);
  }

  // A helix inside the head, its turns 3.4 mm apart along the head axis: every turn cuts new
  // bone, so removal and remeshing never stop.
  std::vector<Waypoint> points;
  const glm::dvec3 w = glm::normalize(model.headAxis);
  const glm::dvec3 u = glm::normalize(glm::cross(w, std::abs(w.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 v = glm::cross(w, u);
  const double radiusMm = 8.0, speedMmPerS = 3.0;
  const double omega = speedMmPerS / radiusMm;
  const double pitchPerS = 3.4 * omega / (2.0 * M_PI);
  for (double t = 0.0; t <= runtimeS + 1e-9; t += 0.05) {
    const glm::dvec3 p = head.centreMm + radiusMm * (std::cos(omega * t) * u + std::sin(omega * t) * v) +
                         (-8.0 + pitchPerS * t) * w;
    const glm::dvec3 tangent = -radiusMm * omega * std::sin(omega * t) * u + radiusMm * omega * std::cos(omega * t) * v;
    points.push_back({t, p, ToolPose::pointing(p, tangent).orientation, true});
  }
  const DrillPath path(points);
  // Each case's sums over the rounds: [case][standby off, on].
  struct Totals {
    std::uint64_t periods = 0, overruns = 0, probePeriods = 0, probeOverruns = 0, minutesMet = 0, runs = 0;
    double stealS = 0.0;
  };
  Totals totals[2][2];
  for (int round = 0; round < rounds; ++round) {
    if (rounds > 1) std::printf("\nround %d of %d\n", round + 1, rounds);
    // The two cases the overrun target names: 1.2 mm with 2 levels, and 0.3 mm static (whose
    // visual thread remeshes 16 times the surface cells).
    for (const auto& [voxelMm, levels] : {std::pair<double, int>{1.2, 2}, {0.3, 0}}) {
      const std::shared_ptr<const BoneModel>& bone = voxelMm == 1.2 ? bone12 : bone03;
      if (round == 0) {
        // The same path in the deterministic mode (one thread, no visual thread): the step's own
        // cost on this path, against which the threaded figures below compare.
        Session alone = makeSession(bone, levels);
        const RunSummary s = alone.run(path).summary;
        std::printf(
            "\nhelix path at %g mm / %d levels, deterministic: step p50 %.1f p99 %.1f max %.1f "
            "us\n",
            voxelMm, levels, s.hapticStepUs.p50, s.hapticStepUs.p99, s.hapticStepUs.max);
      }
      for (const bool withStandby : standbyModes) {
        Session threaded = makeSession(bone, levels);
        PathPoseSource device(path);
        RuntimeOptions ro;
        ro.durationS = runtimeS;
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
        std::printf(
            "threaded runtime, %g s at %g mm / %d levels, helix through the head (started %s)\n",
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
            percentOf(st.collisionOverruns, st.collisionSteps),
            st.collisionStepUs.p50, st.collisionStepUs.p99, st.collisionStepUs.max);
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
  if (rounds > 1) {
    std::printf("\n%d rounds of %g s, summed: haptic overruns against the same-window probe's\n", rounds, runtimeS);
    std::printf("| case | standby | haptic overran | probe overran | haptic - probe | runs within 0.01 | stolen s |\n");
    std::printf("|---|---|---:|---:|---:|---:|---:|\n");
    for (int c = 0; c < 2; ++c) {
      for (int m = 0; m < 2; ++m) {
        const Totals& t = totals[c][m];
        if (t.runs == 0) continue;
        const double h = percentOf(t.overruns, t.periods);
        const double f = percentOf(t.probeOverruns, t.probePeriods);
        std::printf("| %s | %s | %llu of %llu (%.4f %%) | %llu of %llu (%.4f %%) | %+.4f pp | %llu of %llu | %.2f |\n",
                    c == 0 ? "1.2 mm, 2 levels" : "0.3 mm static", m == 1 ? "on" : "off",
                    (unsigned long long)t.overruns, (unsigned long long)t.periods, h,
                    (unsigned long long)t.probeOverruns, (unsigned long long)t.probePeriods, f, h - f,
                    (unsigned long long)t.minutesMet, (unsigned long long)t.runs, t.stealS);
      }
    }
  }
  const OverrunFloor floor = overrunFloor(runtimeS);
  std::printf("\nmachine floor, %g s: the same two 1 kHz loops with no work, a thread streaming memory beside them\n",
              runtimeS);
  std::printf("haptic: %llu periods, %llu overran (%.4f %%); collision: %llu periods, %llu overran (%.4f %%); "
              "stolen %.2f s\n",
              (unsigned long long)floor.periods[0], (unsigned long long)floor.overruns[0],
              percentOf(floor.overruns[0], floor.periods[0]),
              (unsigned long long)floor.periods[1], (unsigned long long)floor.overruns[1],
              percentOf(floor.overruns[1], floor.periods[1]), floor.stealS);
  return 0;
}
