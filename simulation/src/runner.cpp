#include "osteon/simulation/runner.h"

#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include <fcntl.h>
#include <unistd.h>

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

void Durations::add(std::int64_t ns) {
  maxNs_ = std::max(maxNs_, ns);
  ns_.push_back(std::uint32_t(std::clamp<std::int64_t>(ns, 0, std::numeric_limits<std::uint32_t>::max())));
}

void Durations::addMs(double ms) { add(std::int64_t(std::llround(ms * 1e6))); }

Percentiles Durations::percentiles(double nsPerUnit) {
  Percentiles p;
  if (ns_.empty()) return p;
  std::sort(ns_.begin(), ns_.end());
  const auto at = [&](double q) {
    return double(ns_[std::min(ns_.size() - 1, std::size_t(q * double(ns_.size())))]) / nsPerUnit;
  };
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.max = double(maxNs_) / nsPerUnit;
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

// The bounds are forceJitterN's window tests at t = fromS and t = toS, written the same way so
// that rounding keeps every row a window reaches.
ForceMetrics::ForceMetrics(double fromS, double toS, double windowS)
    : fromS_(fromS), toS_(toS), windowS_(windowS), keepFromS_(fromS - 0.5 * windowS - 1e-9),
      keepToS_(toS + 0.5 * windowS + 1e-9) {}

void ForceMetrics::reserveForStep(double stepS) {
  const double rows = (keepToS_ - keepFromS_) / stepS + 3.0;
  if (rows > 0.0 && rows < 1e7) kept_.reserve(std::size_t(rows));
}

void ForceMetrics::add(double tS, double magnitudeN) {
  if (!(tS < keepFromS_) && tS <= keepToS_) {
    kept_.push_back({tS, magnitudeN, sum_});
    sumAfterKept_ = sum_ + magnitudeN;
  }
  sum_ += magnitudeN;
  if (any_) maxStepChangeN_ = std::max(maxStepChangeN_, std::abs(magnitudeN - lastN_));
  lastN_ = magnitudeN;
  any_ = true;
  maxForceN_ = std::max(maxForceN_, magnitudeN);
}

double ForceMetrics::jitterN() const {
  // forceJitterN's loop on the kept rows; the running sums are those of the whole log.
  const std::size_t n = kept_.size();
  const auto sumBefore = [&](std::size_t k) { return k < n ? kept_[k].sumBefore : sumAfterKept_; };
  double sum2 = 0.0;
  std::size_t count = 0, lo = 0, hi = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = kept_[i].tS;
    if (t < fromS_ || t > toS_) continue;
    while (lo < n && kept_[lo].tS < t - 0.5 * windowS_ - 1e-9) ++lo;
    while (hi < n && kept_[hi].tS <= t + 0.5 * windowS_ + 1e-9) ++hi;
    const double mean = (sumBefore(hi) - sumBefore(lo)) / double(hi - lo);
    const double e = kept_[i].magnitudeN - mean;
    sum2 += e * e;
    ++count;
  }
  return count > 0 ? std::sqrt(sum2 / double(count)) : 0.0;
}

RunResult runDeterministic(DrillingSimulation& sim, geometry::VoxelGrid& grid, const DrillPath& path,
                           geometry::SurfaceUpdater* surface, const DeterministicOptions& options) {
  using Clock = std::chrono::steady_clock;
  RunResult result;
  const auto steps = std::size_t(std::llround(path.durationS() / options.stepS)) + 1;
  if (options.keepLog) result.log.reserve(steps);
  ForceMetrics metrics;
  metrics.reserveForStep(options.stepS);
  Durations stepNs, remeshNs;
  stepNs.reserve(steps);
  grid.clearDirty();
  for (std::size_t i = 0; i < steps; ++i) {
    const double t = double(i) * options.stepS;
    StepInput input;
    input.tS = t;
    path.sample(t, input.pose, input.drillOn);  // haptic: the device (here the path) gives the pose
    const Clock::time_point start = Clock::now();
    const HapticStep h = stepHaptic(sim, options.coupling, input);  // coupling, collision, force, removal
    stepNs.add(std::chrono::nanoseconds(Clock::now() - start).count());
    const StepOutput& out = h.step;
    result.summary.tally(h);
    const ForceLogRow row = logRowOf(t, h, sim.totals().samplesRemoved);
    metrics.add(row.tS, row.magnitudeN);
    if (options.onRow) options.onRow(row);
    if (options.keepLog) result.log.push_back(row);
    if (surface && options.remeshEverySteps > 0 && i % std::size_t(options.remeshEverySteps) == 0) {
      const std::vector<std::size_t> dirty = grid.dirtyBricks();  // visual: the surface follows
      if (!dirty.empty()) {
        remeshNs.addMs(surface->update(dirty).ms);
        grid.clearDirty();
      }
    }
    if (options.afterStep) options.afterStep(i, {input.tS, h.proxy, input.drillOn}, out);
    if (interrupted()) break;  // SIGINT/SIGTERM: the caller throws Interrupted
  }
  RunSummary& s = result.summary;
  s.jitterN = metrics.jitterN();
  s.maxStepChangeN = metrics.maxStepChangeN();
  s.maxForceN = metrics.maxForceN();
  s.removedVolumeMm3 = sim.removedVolumeMm3();
  s.hapticStepUs = stepNs.percentiles(1e3);
  s.remeshMs = remeshNs.percentiles(1e6);
  s.steps = steps;
  s.totals = sim.totals();
  s.coupling = options.coupling ? CouplingMode::Proxy : CouplingMode::Direct;
  return result;
}

void writeForceLog(const std::vector<ForceLogRow>& log, const std::string& path, bool commandColumns) {
  ForceLogWriter writer(path, commandColumns);
  for (const ForceLogRow& r : log) writer.write(r);
  writer.commit();
}

namespace {

constexpr char kForceLogHeader[] = "t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level\n";
constexpr char kForceLogHeaderWithCommand[] =
    "t,px,py,pz,cx,cy,cz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level\n";
// The longest row the format can give (every %f at 1e308): formatted only with this much room,
// a row is never cut.
constexpr std::size_t kMaxRowBytes = 4096;

}  // namespace

ForceLogWriter::ForceLogWriter(const std::string& path, bool commandColumns)
    : file_(path), buffer_(std::size_t(1) << 16), commandColumns_(commandColumns) {
  fd_ = ::open(file_.tempPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw InputError(path + ": cannot write the force log (" + std::strerror(errno) + ")");
  const char* header = commandColumns ? kForceLogHeaderWithCommand : kForceLogHeader;
  used_ = std::strlen(header);
  std::memcpy(buffer_.data(), header, used_);
  linesInBuffer_ = 1;
}

ForceLogWriter::~ForceLogWriter() {
  if (done_) return;
  if (interrupted()) {  // stopped on request (SIGINT/SIGTERM): nothing kept, the folder stays as it was
    if (fd_ >= 0) ::close(fd_);
    return;  // file_ removes the temporary
  }
  keepPartial();
}

long ForceLogWriter::writeSome(int fd, const char* data, std::size_t bytes) noexcept {
  return long(::write(fd, data, bytes));
}

void ForceLogWriter::write(const ForceLogRow& r) noexcept {
  if (error_ != 0 || fd_ < 0) return;
  if (buffer_.size() - used_ < kMaxRowBytes) {
    flush();
    if (error_ != 0) return;
  }
  const int n =
      commandColumns_
          ? std::snprintf(buffer_.data() + used_, buffer_.size() - used_,
                          "%.3f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.9g,%.9g,%.9g,%.9g,%.6g,%llu,%d\n", r.tS, r.tipMm.x,
                          r.tipMm.y, r.tipMm.z, r.commandMm.x, r.commandMm.y, r.commandMm.z, r.forceN.x, r.forceN.y,
                          r.forceN.z, r.magnitudeN, r.contactVoxels, static_cast<unsigned long long>(r.removedVoxels),
                          r.level)
          : std::snprintf(buffer_.data() + used_, buffer_.size() - used_,
                          "%.3f,%.6f,%.6f,%.6f,%.9g,%.9g,%.9g,%.9g,%.6g,%llu,%d\n", r.tS, r.tipMm.x, r.tipMm.y,
                          r.tipMm.z, r.forceN.x, r.forceN.y, r.forceN.z, r.magnitudeN, r.contactVoxels,
                          static_cast<unsigned long long>(r.removedVoxels), r.level);
  if (n > 0 && std::size_t(n) < buffer_.size() - used_) {
    used_ += std::size_t(n);
    ++linesInBuffer_;
  }
}

void ForceLogWriter::flush() noexcept {
  if (error_ != 0 || fd_ < 0 || used_ == 0) return;
  std::size_t written = 0;
  while (written < used_) {
    const long n = writeSome(fd_, buffer_.data() + written, used_ - written);
    if (n > 0) {
      written += std::size_t(n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      error_ = n < 0 ? errno : EIO;  // no progress at all: as good as an error
      break;
    }
  }
  if (error_ != 0) {
    // The disk took part of the buffer: cut what it took back to the last whole row.
    std::size_t whole = written;
    while (whole > 0 && buffer_[whole - 1] != '\n') --whole;
    if (whole < written && ::ftruncate(fd_, off_t(bytesOnDisk_ + whole)) != 0) torn_ = true;
    linesOnDisk_ += std::uint64_t(std::count(buffer_.data(), buffer_.data() + whole, '\n'));
    bytesOnDisk_ += whole;
  } else {
    linesOnDisk_ += linesInBuffer_;
    bytesOnDisk_ += used_;
  }
  used_ = 0;
  linesInBuffer_ = 0;
}

std::uint64_t ForceLogWriter::keepPartial() noexcept {
  done_ = true;
  flush();
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  if (torn_ || rowsOnDisk() == 0) return 0;  // the temporary goes with file_
  try {
    file_.commitTo(partialPath());
  } catch (...) {
    return 0;
  }
  return rowsOnDisk();
}

void ForceLogWriter::commit() {
  if (done_) return;
  flush();
  if (::close(fd_) != 0 && error_ == 0) error_ = errno;  // a deferred write error shows here
  fd_ = -1;
  if (error_ == 0) {
    done_ = true;
    file_.commit();
    std::remove(partialPath().c_str());  // left by an earlier run that failed: this one did not
    return;
  }
  const int error = error_;
  const std::uint64_t kept = keepPartial();
  throw InputError(path() + ": cannot write the force log (" + std::strerror(error) + "); " + keptNote(kept));
}

std::string ForceLogWriter::abandon() {
  if (done_) return "the force log was already closed";
  return keptNote(keepPartial());
}

std::string ForceLogWriter::keptNote(std::uint64_t kept) const {
  if (kept == 0) return "no row of the force log reached the disk";
  return "the " + std::to_string(kept) + " rows written before it are kept in " + partialPath();
}

}  // namespace osteon::simulation
