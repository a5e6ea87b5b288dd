// The deterministic mode (for tests and experiments): haptic, collision-and-removal and visual
// work stepped in one thread with a fixed 1 ms step, so the same input gives the same force
// log bit for bit. Also the force log, and the metrics of design.md.
#pragma once

#include "osteon/geometry/io/output_file.h"
#include "osteon/geometry/surface/surface_updater.h"
#include "osteon/simulation/coupling.h"
#include "osteon/simulation/drilling.h"
#include "osteon/simulation/path.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
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
  glm::dvec3 commandMm{0.0};        // the commanded tip (proxy coupling; tipMm is the proxy's)
};

// The log row of one step: the pose it took, its force, the samples removed so far.
inline ForceLogRow logRowOf(double tS, const ToolPose& pose, const StepOutput& out, std::uint64_t samplesRemoved) {
  return {tS, pose.tipMm, out.contact.forceN, out.contact.magnitudeN, out.contact.contactVoxels, samplesRemoved,
          out.contact.level};
}

// The log row of one haptic step (coupling.h): the proxy's tip, the force sent to the device,
// the commanded tip. Under direct coupling the same row as logRowOf(tS, pose, out, ...).
inline ForceLogRow logRowOf(double tS, const HapticStep& h, std::uint64_t samplesRemoved) {
  return {tS, h.proxy.tipMm, h.forceN, h.magnitudeN, h.step.contact.contactVoxels, samplesRemoved,
          h.step.contact.level, h.commanded.tipMm};
}

struct Percentiles {
  double p50 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
};
Percentiles percentilesOf(std::vector<double> values);

// Durations in whole nanoseconds, 4 bytes each: exact percentiles of a long run in little
// memory. add() allocates only past the reserved capacity.
class Durations {
 public:
  // Room for n durations, its pages written now: a first write to a fresh page in a 1 kHz
  // loop is a page fault, which waits whenever another thread holds the address space's lock
  // (an munmap of a freed surface buffer), often past the period.
  void reserve(std::size_t n) {
    ns_.assign(n, 0u);
    ns_.clear();
  }
  bool full() const { return ns_.size() >= ns_.capacity(); }
  void add(std::int64_t ns);
  // A duration chrono gave in milliseconds from whole nanoseconds: kept exactly.
  void addMs(double ms);
  // As percentilesOf() on ns / nsPerUnit (1e3: microseconds, 1e6: milliseconds). Sorts.
  Percentiles percentiles(double nsPerUnit);

 private:
  std::vector<std::uint32_t> ns_;  // saturated at 4.29 s; the max is kept apart
  std::int64_t maxNs_ = 0;
};

struct RunSummary {
  double jitterN = 0.0;           // design.md: RMS of |F| minus its 50 ms centred moving average, t in [2, 5] s
  double maxStepChangeN = 0.0;    // largest |F| change between consecutive samples
  double maxForceN = 0.0;
  double removedVolumeMm3 = 0.0;
  Percentiles hapticStepUs;       // collision + force + removal per step
  Percentiles remeshMs;           // incremental surface updates
  std::uint64_t overruns = 0;     // steps over their period (threaded runtime; 0 here)
  std::uint64_t steps = 0;
  DrillingTotals totals;  // the simulation's counters at the end of the run (drilling.h)
  CouplingMode coupling = CouplingMode::Direct;
  double maxGapMm = 0.0;          // largest proxy-to-commanded tip distance (0 under direct)
  std::uint64_t clampSteps = 0;   // steps whose force to the device was at N_max
  // Counts one haptic step in maxGapMm and clampSteps.
  void tally(const HapticStep& h) {
    maxGapMm = std::max(maxGapMm, h.gapMm);
    clampSteps += h.clamped ? 1 : 0;
  }
};

// Jitter as design.md defines it; 0 when no sample lies in [fromS, toS].
double forceJitterN(const std::vector<ForceLogRow>& log, double fromS = 2.0, double toS = 5.0,
                    double windowS = 0.05);
double maxStepChangeN(const std::vector<ForceLogRow>& log);

// The summary's force metrics from rows given one at a time in time order, bit for bit those
// of forceJitterN, maxStepChangeN and the largest |F| on the whole log, keeping only the rows
// the jitter's windows reach (t in [fromS - windowS / 2, toS + windowS / 2]).
class ForceMetrics {
 public:
  explicit ForceMetrics(double fromS = 2.0, double toS = 5.0, double windowS = 0.05);
  // Room for the kept rows at this step, so that add() does not allocate.
  void reserveForStep(double stepS);
  void add(double tS, double magnitudeN);
  double jitterN() const;
  double maxStepChangeN() const { return maxStepChangeN_; }
  double maxForceN() const { return maxForceN_; }

 private:
  struct Kept {
    double tS, magnitudeN, sumBefore;  // sumBefore: of |F| over every earlier row
  };
  double fromS_, toS_, windowS_, keepFromS_, keepToS_;
  std::vector<Kept> kept_;
  double sum_ = 0.0;           // of |F| over every row so far
  double sumAfterKept_ = 0.0;  // ... up to and including the last kept row
  double lastN_ = 0.0;
  bool any_ = false;
  double maxStepChangeN_ = 0.0, maxForceN_ = 0.0;
};

struct DeterministicOptions {
  double stepS = 0.001;
  int remeshEverySteps = 1;  // the visual work: incremental surface update every N steps
  // Called after each step (and its surface update), for checks that follow a run.
  std::function<void(std::size_t step, const StepInput& input, const StepOutput& output)> afterStep;
  // Rows as they come (e.g. ForceLogWriter::write); must not throw.
  std::function<void(const ForceLogRow& row)> onRow;
  // The proxy coupling the run steps through (coupling.h); null: direct, the path's pose is
  // the tool's. afterStep then sees the proxy's pose.
  ProxyCoupling* coupling = nullptr;
  // Also collects every row in RunResult::log: for short paths (tests, experiments); the CLI
  // streams through onRow instead, so memory does not grow with the path.
  bool keepLog = true;
};

struct RunResult {
  std::vector<ForceLogRow> log;
  RunSummary summary;
};

// Runs the path from t = 0 to its end, or until SIGINT/SIGTERM is recorded (core/interrupt.h:
// the caller then throws Interrupted). `surface` may be null (no visual work).
RunResult runDeterministic(DrillingSimulation& sim, geometry::VoxelGrid& grid, const DrillPath& path,
                           geometry::SurfaceUpdater* surface, const DeterministicOptions& options = {});

// CSV with a header row: t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level
// (with commandColumns, as proxy coupling writes it: t,px,py,pz,cx,cy,cz,fx,...: the proxy's
// tip, then the commanded one).
// Throws InputError naming the file when it cannot be written.
void writeForceLog(const std::vector<ForceLogRow>& log, const std::string& path, bool commandColumns = false);

// The same CSV row by row as a run goes: written to a temporary file beside `path` and put in
// place by commit(), so path() only ever holds a complete log. write() neither allocates, locks
// nor throws: rows are formatted into a buffer that goes to the file whole. When the disk fails
// (full, over quota, an I/O error) the file is cut back to its last whole row and later rows
// are dropped; commit() then keeps the rows written in partialPath() and throws. A writer
// destroyed without commit() (a run that failed elsewhere) keeps its whole rows there too,
// unless the run was stopped by SIGINT/SIGTERM (core/interrupt.h): then it keeps nothing.
class ForceLogWriter {
 public:
  // throws InputError naming path; commandColumns: cx,cy,cz after px,py,pz (proxy coupling)
  explicit ForceLogWriter(const std::string& path, bool commandColumns = false);
  virtual ~ForceLogWriter();
  ForceLogWriter(const ForceLogWriter&) = delete;
  ForceLogWriter& operator=(const ForceLogWriter&) = delete;

  const std::string& path() const { return file_.path(); }
  std::string partialPath() const { return file_.path() + ".partial"; }
  void write(const ForceLogRow& row) noexcept;
  // True once a write to the file has failed (the rows after it are dropped).
  bool failed() const { return error_ != 0; }
  // Puts the log in place, and removes a partialPath() left by an earlier failed run. After a
  // failed write it keeps the whole rows written before it in partialPath() and throws an
  // InputError naming the file, the reason and how many rows were kept.
  void commit();
  // For a run that failed part-way: keeps the whole rows written so far in partialPath(), as
  // destruction would, and says where in words for the run's one-line error.
  std::string abandon();

 protected:
  // write(2) on the temporary file: the bytes written, maybe fewer than asked, or -1 and errno.
  // A seam for tests, which fail it as a full disk does; called once per 64 KiB of rows.
  virtual long writeSome(int fd, const char* data, std::size_t bytes) noexcept;

 private:
  void flush() noexcept;
  // Closes the file and keeps its whole rows in partialPath(); the rows kept (0: no file).
  std::uint64_t keepPartial() noexcept;
  std::uint64_t rowsOnDisk() const { return linesOnDisk_ > 0 ? linesOnDisk_ - 1 : 0; }
  std::string keptNote(std::uint64_t kept) const;

  geometry::OutputFile file_;
  std::vector<char> buffer_;
  std::size_t used_ = 0;
  std::uint64_t linesInBuffer_ = 0;   // the header counts as a line
  std::uint64_t linesOnDisk_ = 0, bytesOnDisk_ = 0;
  int fd_ = -1;
  int error_ = 0;      // errno of the first failed write
  bool torn_ = false;  // a failed write's tail could not be cut off: the file is not kept
  bool done_ = false;  // committed or kept
  bool commandColumns_ = false;
};

}  // namespace osteon::simulation
