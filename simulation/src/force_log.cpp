#include "osteon/simulation/force_log.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <unistd.h>

#include "osteon/core/assert.h"
#include "osteon/core/error.h"
#include "osteon/core/interrupt.h"

namespace osteon::simulation {

void writeForceLog(const std::vector<ForceLogRow>& log, const std::string& path,
                   bool commandColumns, bool feelColumns) {
  ForceLogWriter writer(path, commandColumns, feelColumns);
  for (const ForceLogRow& r : log) writer.write(r);
  writer.commit();
}

namespace {

constexpr char kForceLogHeader[] =
    "t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level\n";
constexpr char kForceLogHeaderWithCommand[] =
    "t,px,py,pz,cx,cy,cz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level\n";
// The calibrated model's columns, after the others (cutting.h).
constexpr char kFeelColumns[] = ",rpm,irrigation,removed_mm3,temperature_c";
// The longest row the format can give (every %f at 1e308): formatted only with this much room,
// a row is never cut.
constexpr std::size_t kMaxRowBytes = 4096;

}  // namespace

ForceLogWriter::ForceLogWriter(const std::string& path, bool commandColumns, bool feelColumns)
    : file_(path),
      buffer_(std::size_t(1) << 16),
      commandColumns_(commandColumns),
      feelColumns_(feelColumns) {
  fd_ = ::open(file_.tempPath().c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0)
    throw InputError(path + ": cannot write the force log (" + std::strerror(errno) + ")");
  std::string header = commandColumns ? kForceLogHeaderWithCommand : kForceLogHeader;
  if (feelColumns) header.insert(header.size() - 1, kFeelColumns);
  used_ = header.size();
  std::memcpy(buffer_.data(), header.data(), used_);
  linesInBuffer_ = 1;
}

ForceLogWriter::~ForceLogWriter() {
  if (done_) return;
  if (interrupted()) {  // stopped on request (SIGINT/SIGTERM): nothing kept, the folder stays as it
                        // was
    if (fd_ >= 0) ::close(fd_);
    return;  // file_ removes the temporary
  }
  keepPartial();
}

long ForceLogWriter::writeSome(int fd, const char* data, std::size_t bytes) noexcept {
  return long(::write(fd, data, bytes));
}

void ForceLogWriter::write(const ForceLogRow& r) noexcept {
  if (tap_) tap_->row(r);
  if (error_ != 0 || fd_ < 0) return;
  if (buffer_.size() - used_ < kMaxRowBytes) {
    flush();
    if (error_ != 0) return;
  }
  const int n =
      commandColumns_
          ? std::snprintf(buffer_.data() + used_, buffer_.size() - used_,
                          "%.3f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.9g,%.9g,%.9g,%.9g,%.6g,%llu,%d\n",
                          r.tS, r.tipMm.x, r.tipMm.y, r.tipMm.z, r.commandMm.x, r.commandMm.y,
                          r.commandMm.z, r.forceN.x, r.forceN.y, r.forceN.z, r.magnitudeN,
                          r.contactVoxels, static_cast<unsigned long long>(r.removedVoxels),
                          r.level)
          : std::snprintf(buffer_.data() + used_, buffer_.size() - used_,
                          "%.3f,%.6f,%.6f,%.6f,%.9g,%.9g,%.9g,%.9g,%.6g,%llu,%d\n", r.tS, r.tipMm.x,
                          r.tipMm.y, r.tipMm.z, r.forceN.x, r.forceN.y, r.forceN.z, r.magnitudeN,
                          r.contactVoxels, static_cast<unsigned long long>(r.removedVoxels),
                          r.level);
  OSTEON_ASSERT(n > 0 && std::size_t(n) < kMaxRowBytes,
                "a row fits the room kept for the longest one");
  if (feelColumns_ && n > 0) {
    // The row's newline gives way to the feel columns and a newline of their own.
    const std::size_t at = used_ + std::size_t(n) - 1;
    const int more = std::snprintf(buffer_.data() + at, buffer_.size() - at, ",%.0f,%d,%.6g,%.3f\n",
                                   r.rpm, r.irrigation ? 1 : 0, r.removedMm3, r.temperatureC);
    if (more > 0 && std::size_t(more) < buffer_.size() - at) {
      used_ = at + std::size_t(more);
      ++linesInBuffer_;
    }
    return;
  }
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
  throw InputError(path() + ": cannot write the force log (" + std::strerror(error) + "); " +
                   keptNote(kept));
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
