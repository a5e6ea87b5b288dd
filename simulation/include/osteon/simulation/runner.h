// The deterministic mode (for tests and experiments): haptic, collision-and-removal and visual
// work stepped in one thread with a fixed 1 ms step, so the same input gives the same force
// log bit for bit. Also the force log, and the metrics of design.md.
#pragma once

#include "osteon/geometry/surface_updater.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/path.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace osteon::simulation {

struct ForceLogRow {
  double tS = 0.0;
  glm::dvec3 tipMm{0.0};
  glm::dvec3 forceN{0.0};
  double magnitudeN = 0.0;
  double contactVoxels = 0.0;       // n of eq. (2)
  std::uint64_t removedVoxels = 0;  // samples removed so far (at the level they were cut)
  int level = 0;                    // finest level in contact
};

struct Percentiles {
  double p50 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
};
Percentiles percentilesOf(std::vector<double> values);

struct RunSummary {
  double jitterN = 0.0;           // design.md: RMS of |F| minus its 50 ms centred moving average, t in [2, 5] s
  double maxStepChangeN = 0.0;    // largest |F| change between consecutive samples
  double maxForceN = 0.0;
  double removedVolumeMm3 = 0.0;
  Percentiles hapticStepUs;       // collision + force + removal per step
  Percentiles remeshMs;           // incremental surface updates
  std::uint64_t overruns = 0;     // steps over their period (threaded runtime; 0 here)
  std::uint64_t steps = 0;
  std::uint64_t nonFiniteForces = 0;
  std::uint64_t cutOverflows = 0;      // cuts that found more voxels than reserved room (0: none)
  std::uint64_t refinePoolExhausted = 0;  // voxels left unrefined near the tool: the pool was full (0: none)
  std::uint64_t maskOverflows = 0;        // removal masks not kept: their table was full (0: none)
  std::uint64_t brickAllocations = 0;  // heap allocations in the drilling steps (0: the pool sufficed)
};

// Jitter as design.md defines it; 0 when no sample lies in [fromS, toS].
double forceJitterN(const std::vector<ForceLogRow>& log, double fromS = 2.0, double toS = 5.0,
                    double windowS = 0.05);
double maxStepChangeN(const std::vector<ForceLogRow>& log);

struct DeterministicOptions {
  double stepS = 0.001;
  int remeshEverySteps = 1;  // the visual work: incremental surface update every N steps
  // Called after each step (and its surface update), for checks that follow a run.
  std::function<void(std::size_t step, const StepInput& input, const StepOutput& output)> afterStep;
};

struct RunResult {
  std::vector<ForceLogRow> log;
  RunSummary summary;
};

// Runs the path from t = 0 to its end. `surface` may be null (no visual work).
RunResult runDeterministic(DrillingSimulation& sim, geometry::VoxelGrid& grid, const DrillPath& path,
                           geometry::SurfaceUpdater* surface, const DeterministicOptions& options = {});

// CSV with a header row: t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level.
// Throws InputError naming the file when it cannot be written.
void writeForceLog(const std::vector<ForceLogRow>& log, const std::string& path);

}  // namespace osteon::simulation
