// Recording and replay of any device's stream. A recording is CSV with a header row
//   t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on,rpm,irrigation
// (seconds, millimetres, the orientation quaternion, the button mask, the pedal 0..1, the
// drill trigger 0/1, the drill's rpm and irrigation 0/1 as the run used them; recordings
// without the last two, as osteon wrote them before, still load), one row per new sample (1 kHz
// from a haptic loop), numbers in their shortest form that reads back to the same double, so a
// replay reproduces its run bit for bit. Non-finite pose values are written as nan/inf: a replay
// meets them as the device fault they were. The writer puts rows in a lock-free buffer from the
// haptic loop and a thread of its own writes them to the file every 100 ms, so a crash loses at
// most that.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "osteon/devices/device.h"

namespace osteon::devices {

inline constexpr const char* kRecordingHeader =
    "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on,rpm,irrigation";
// The header of recordings without the drill's settings (read as unknown: rpm 0).
inline constexpr const char* kRecordingHeaderWithoutSettings =
    "t,x,y,z,qw,qx,qy,qz,buttons,pedal,drill_on";
// The longest recording a replay accepts (an hour, as drill paths), and its rows.
inline constexpr double kMaxRecordingS = 3600.0;
inline constexpr std::size_t kMaxRecordingRows = 4'000'000;

// One row as text with its newline, at time tS. Returns the bytes written, 0 when `size` is too
// small (256 bytes always suffice). No allocation.
std::size_t formatRecordingRow(double tS, const DeviceSample& sample, char* out,
                               std::size_t size) noexcept;

struct RecorderOptions {
  double flushEveryS = 0.1;            // the writer thread's period
  std::size_t bufferBytes = 4u << 20;  // about 25 s of rows at 1 kHz
  // Deterministic runs (faster than real time) wait for room instead of dropping a row; live
  // loops drop and count (a real-time loop never waits for a disk).
  bool waitWhenFull = false;
  // The file messages name, when the recorder writes a temporary that becomes it (as through
  // geometry's OutputFile, which keeps an existing recording until the new one is complete).
  // Empty: the path written.
  std::string name;
};

class StreamRecorder {
 public:
  // Creates (truncates) the file and writes the header. Throws InputError naming the path
  // (options.name when given). To keep an existing recording until the new one is complete,
  // record into a temporary and rename it when close() succeeds.
  explicit StreamRecorder(const std::string& path, const RecorderOptions& options = {});
  ~StreamRecorder();
  StreamRecorder(const StreamRecorder&) = delete;
  StreamRecorder& operator=(const StreamRecorder&) = delete;

  // One row; from one thread (the haptic loop). No allocation, no lock, no system call unless
  // waitWhenFull and the buffer is full.
  void record(double tS, const DeviceSample& sample) noexcept;
  // Writes what is left and closes the file. Throws InputError naming the path when a write
  // failed (disk full). Called by the destructor too (which swallows the error).
  void close();

  const std::string& path() const { return path_; }
  std::uint64_t rows() const { return rows_.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  void writerLoop();
  bool drain();

  std::string path_;
  std::string name_;  // in messages
  RecorderOptions options_;
  int fd_ = -1;
  std::vector<char> ring_;
  std::atomic<std::uint64_t> head_{0};  // bytes produced
  std::atomic<std::uint64_t> tail_{0};  // bytes written
  std::atomic<std::uint64_t> rows_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<bool> failed_{false};
  int error_ = 0;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  bool woken_ = false;
  std::thread writer_;
};

struct RecordingRow {
  double tS = 0.0;
  glm::dvec3 positionMm{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
  std::uint32_t buttons = 0;
  double pedal = 0.0;
  bool drillOn = false;
  double rpm = 0.0;  // 0: not recorded
  bool irrigation = false;
};

// A recording read whole. Rows with non-finite pose values are kept (device faults for the
// safety layer to meet); anything that is not such a CSV (no header, a wrong field count, text
// where a number belongs, times that are not finite or do not increase, more than an hour) is
// an InputError naming the file and line.
struct Recording {
  std::string path;
  std::vector<RecordingRow> rows;
  double startS() const { return rows.empty() ? 0.0 : rows.front().tS; }
  double endS() const { return rows.empty() ? 0.0 : rows.back().tS; }
};
Recording loadRecording(const std::string& path);

// `replay:LOG.csv`: the recorded stream, time-driven. poll(t) gives the newest row at or
// before t (rows are the recording loop's periods: capabilities().recorded).
class ReplayDevice final : public Device {
 public:
  ReplayDevice(const std::string& name, Recording recording);
  Capabilities capabilities() const override;
  void poll(double nowS, DeviceSample& sample) noexcept override;
  const Recording& recording() const { return recording_; }

 private:
  Recording recording_;
  std::size_t next_ = 0;  // first row not yet given
};

}  // namespace osteon::devices
