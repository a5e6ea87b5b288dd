#include "osteon/simulation/runner.h"

#include "osteon/geometry/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace osteon::simulation {

Percentiles percentilesOf(std::vector<double> values) {
  Percentiles p;
  if (values.empty()) return p;
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) {
    return values[std::min(values.size() - 1, std::size_t(q * double(values.size())))];
  };
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.max = values.back();
  return p;
}

double forceJitterN(const std::vector<ForceLogRow>& log, double fromS, double toS, double windowS) {
  // Prefix sums of |F| make every centred window O(1).
  std::vector<double> prefix(log.size() + 1, 0.0);
  for (std::size_t i = 0; i < log.size(); ++i) prefix[i + 1] = prefix[i] + log[i].magnitudeN;
  double sum2 = 0.0;
  std::size_t count = 0, lo = 0, hi = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    const double t = log[i].tS;
    if (t < fromS || t > toS) continue;
    // A nanosecond of slack keeps the window symmetric (51 samples at 1 ms) despite rounding.
    while (lo < log.size() && log[lo].tS < t - 0.5 * windowS - 1e-9) ++lo;
    while (hi < log.size() && log[hi].tS <= t + 0.5 * windowS + 1e-9) ++hi;
    const double mean = (prefix[hi] - prefix[lo]) / double(hi - lo);
    const double e = log[i].magnitudeN - mean;
    sum2 += e * e;
    ++count;
  }
  return count > 0 ? std::sqrt(sum2 / double(count)) : 0.0;
}

double maxStepChangeN(const std::vector<ForceLogRow>& log) {
  double m = 0.0;
  for (std::size_t i = 1; i < log.size(); ++i) m = std::max(m, std::abs(log[i].magnitudeN - log[i - 1].magnitudeN));
  return m;
}

RunResult runDeterministic(DrillingSimulation& sim, geometry::VoxelGrid& grid, const DrillPath& path,
                           geometry::SurfaceUpdater* surface, const DeterministicOptions& options) {
  using Clock = std::chrono::steady_clock;
  RunResult result;
  const auto steps = std::size_t(std::llround(path.durationS() / options.stepS)) + 1;
  result.log.reserve(steps);
  std::vector<double> stepUs, remeshMs;
  stepUs.reserve(steps);
  grid.clearDirty();
  for (std::size_t i = 0; i < steps; ++i) {
    const double t = double(i) * options.stepS;
    StepInput input;
    input.tS = t;
    path.sample(t, input.pose, input.drillOn);  // haptic: the device (here the path) gives the pose
    const Clock::time_point start = Clock::now();
    const StepOutput out = sim.step(input);    // collision, force, removal
    stepUs.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
    ForceLogRow row;
    row.tS = t;
    row.tipMm = input.pose.tipMm;
    row.forceN = out.contact.forceN;
    row.magnitudeN = out.contact.magnitudeN;
    row.contactVoxels = out.contact.contactVoxels;
    row.removedVoxels = sim.totals().samplesRemoved;
    row.level = out.contact.level;
    result.log.push_back(row);
    if (surface && options.remeshEverySteps > 0 && i % std::size_t(options.remeshEverySteps) == 0) {
      const std::vector<std::size_t> dirty = grid.dirtyBricks();  // visual: the surface follows
      if (!dirty.empty()) {
        remeshMs.push_back(surface->update(dirty).ms);
        grid.clearDirty();
      }
    }
    if (options.afterStep) options.afterStep(i, input, out);
  }
  RunSummary& s = result.summary;
  s.jitterN = forceJitterN(result.log);
  s.maxStepChangeN = maxStepChangeN(result.log);
  for (const ForceLogRow& r : result.log) s.maxForceN = std::max(s.maxForceN, r.magnitudeN);
  s.removedVolumeMm3 = sim.removedVolumeMm3();
  s.hapticStepUs = percentilesOf(stepUs);
  s.remeshMs = percentilesOf(remeshMs);
  s.steps = steps;
  s.nonFiniteForces = sim.totals().nonFiniteForces;
  s.brickAllocations = sim.totals().brickAllocations;
  s.cutOverflows = sim.totals().cutOverflows;
  s.refinePoolExhausted = sim.totals().refinePoolExhausted;
  s.maskOverflows = sim.totals().maskOverflows;
  return result;
}

void writeForceLog(const std::vector<ForceLogRow>& log, const std::string& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!f) throw InputError(path + ": cannot write the force log");
  std::fputs("t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level\n", f.get());
  for (const ForceLogRow& r : log) {
    std::fprintf(f.get(), "%.3f,%.6f,%.6f,%.6f,%.9g,%.9g,%.9g,%.9g,%.6g,%llu,%d\n", r.tS, r.tipMm.x,
                 r.tipMm.y, r.tipMm.z, r.forceN.x, r.forceN.y, r.forceN.z, r.magnitudeN, r.contactVoxels,
                 static_cast<unsigned long long>(r.removedVoxels), r.level);
  }
  if (std::ferror(f.get())) throw InputError(path + ": write failed (disk full?)");
}

}  // namespace osteon::simulation
