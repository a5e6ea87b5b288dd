// The force log: one row per haptic step (the pose, the force sent, the bone removed so far),
// and its CSV, written whole or streamed row by row as a run goes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "osteon/geometry/io/output_file.h"
#include "osteon/simulation/coupling.h"
#include "osteon/simulation/drilling.h"

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
  // Under the calibrated model (cutting.h) only; the seed's log has no columns for them.
  double rpm = 0.0;
  bool irrigation = false;
  double removedMm3 = 0.0;     // bone removed so far
  double temperatureC = 37.0;  // at the tip (the heat model's)
};

// The log row of one step: the pose it took, its force, the samples removed so far.
inline ForceLogRow logRowOf(double tS, const ToolPose& pose, const StepOutput& out,
                            std::uint64_t samplesRemoved) {
  return {tS,
          pose.tipMm,
          out.contact.forceN,
          out.contact.magnitudeN,
          out.contact.contactVoxels,
          samplesRemoved,
          out.contact.level};
}

// The log row of one haptic step (coupling.h): the proxy's tip, the force sent to the device,
// the commanded tip. Under direct coupling the same row as logRowOf(tS, pose, out, ...).
inline ForceLogRow logRowOf(double tS, const HapticStep& h, std::uint64_t samplesRemoved) {
  return {tS,
          h.proxy.tipMm,
          h.forceN,
          h.magnitudeN,
          h.step.contact.contactVoxels,
          samplesRemoved,
          h.step.contact.level,
          h.commanded.tipMm};
}

// The same row with what the step ran under and the bone removed so far (every run fills it;
// the calibrated model's log writes them).
inline ForceLogRow logRowOf(const StepInput& in, const HapticStep& h,
                            const DrillingSimulation& sim) {
  ForceLogRow row = logRowOf(in.tS, h, sim.totals().samplesRemoved);
  row.rpm = in.settings.rpm;
  row.irrigation = in.settings.irrigation;
  row.removedMm3 = sim.removedVolumeMm3();
  row.temperatureC = h.temperatureC;
  return row;
}

// CSV with a header row: t,px,py,pz,fx,fy,fz,f_mag,contact_voxels,removed_voxels,level
// (with commandColumns, as proxy coupling writes it: t,px,py,pz,cx,cy,cz,fx,...: the proxy's
// tip, then the commanded one).
// Throws InputError naming the file when it cannot be written.
// feelColumns (the calibrated model's runs): rpm,irrigation,removed_mm3,temperature_c after
// the others.
void writeForceLog(const std::vector<ForceLogRow>& log, const std::string& path,
                   bool commandColumns = false, bool feelColumns = false);

// What else follows a run's rows as they are logged (the drill's sound of --audio-out): given
// every row by ForceLogWriter::write, on its thread, so it must not allocate, lock or throw.
class RowTap {
 public:
  virtual ~RowTap() = default;
  virtual void row(const ForceLogRow& row) noexcept = 0;
};

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
  explicit ForceLogWriter(const std::string& path, bool commandColumns = false,
                          bool feelColumns = false);
  virtual ~ForceLogWriter();
  ForceLogWriter(const ForceLogWriter&) = delete;
  ForceLogWriter& operator=(const ForceLogWriter&) = delete;

  const std::string& path() const { return file_.path(); }
  std::string partialPath() const { return file_.path() + ".partial"; }
  void write(const ForceLogRow& row) noexcept;
  // Every row written from now on is given to tap too (nullptr: none); it outlives the run.
  void tapRows(RowTap* tap) { tap_ = tap; }
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
  std::uint64_t linesInBuffer_ = 0;  // the header counts as a line
  std::uint64_t linesOnDisk_ = 0, bytesOnDisk_ = 0;
  int fd_ = -1;
  int error_ = 0;      // errno of the first failed write
  bool torn_ = false;  // a failed write's tail could not be cut off: the file is not kept
  bool done_ = false;  // committed or kept
  bool commandColumns_ = false;
  bool feelColumns_ = false;
  RowTap* tap_ = nullptr;
};

}  // namespace osteon::simulation
