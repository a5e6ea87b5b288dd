#include "osteon/devices/recording.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <memory>
#include <sstream>
#include <unistd.h>

#include "osteon/core/error.h"
#include "osteon/core/input_file.h"

namespace osteon::devices {

namespace {

// Appends a double in its shortest round-trip form (nan, inf and -inf as such).
char* putDouble(char* p, char* end, double v) {
  const std::to_chars_result r = std::to_chars(p, end, v);
  return r.ec == std::errc() ? r.ptr : nullptr;
}

}  // namespace

std::size_t formatRecordingRow(double tS, const DeviceSample& s, char* out,
                               std::size_t size) noexcept {
  char* p = out;
  char* const end = out + size;
  const double values[8] = {tS,
                            s.positionMm.x,
                            s.positionMm.y,
                            s.positionMm.z,
                            s.orientation.w,
                            s.orientation.x,
                            s.orientation.y,
                            s.orientation.z};
  for (double v : values) {
    if (!(p = putDouble(p, end, v)) || p == end) return 0;
    *p++ = ',';
  }
  std::to_chars_result r = std::to_chars(p, end, s.buttons);
  if (r.ec != std::errc() || r.ptr == end) return 0;
  p = r.ptr;
  *p++ = ',';
  if (!(p = putDouble(p, end, s.pedal)) || end - p < 3) return 0;
  *p++ = ',';
  *p++ = s.drillOn ? '1' : '0';
  *p++ = ',';
  if (!(p = putDouble(p, end, s.rpm)) || end - p < 3) return 0;
  *p++ = ',';
  *p++ = s.irrigation ? '1' : '0';
  *p++ = '\n';
  return std::size_t(p - out);
}

// ---- writing ----

StreamRecorder::StreamRecorder(const std::string& path, const RecorderOptions& options)
    : path_(path),
      name_(options.name.empty() ? path : options.name),
      options_(options),
      ring_(std::max<std::size_t>(options.bufferBytes, 4096)) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw InputError(name_ + ": cannot write the recording (" + std::strerror(errno) + ")");
  const std::string header = std::string(kRecordingHeader) + "\n";
  if (::write(fd_, header.data(), header.size()) != ssize_t(header.size())) {
    const int e = errno;
    ::close(fd_);
    fd_ = -1;
    throw InputError(name_ + ": cannot write the recording (" + std::strerror(e) + ")");
  }
  writer_ = std::thread([this] { writerLoop(); });
}

StreamRecorder::~StreamRecorder() {
  try {
    close();
  } catch (const InputError&) {
    // reported by an explicit close(); a destructor must not throw
  }
}

void StreamRecorder::record(double tS, const DeviceSample& sample) noexcept {
  char line[256];
  const std::size_t n = formatRecordingRow(tS, sample, line, sizeof line);
  if (n == 0 || fd_ < 0) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const std::uint64_t capacity = ring_.size();
  const std::uint64_t head = head_.load(std::memory_order_relaxed);
  while (capacity - (head - tail_.load(std::memory_order_acquire)) < n) {
    if (!options_.waitWhenFull || failed_.load(std::memory_order_relaxed)) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      woken_ = true;
    }
    wake_.notify_one();
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  const std::size_t at = std::size_t(head % capacity);
  const std::size_t first = std::min<std::size_t>(n, ring_.size() - at);
  std::memcpy(ring_.data() + at, line, first);
  std::memcpy(ring_.data(), line + first, n - first);
  head_.store(head + n, std::memory_order_release);
  rows_.fetch_add(1, std::memory_order_relaxed);
}

bool StreamRecorder::drain() {
  const std::uint64_t head = head_.load(std::memory_order_acquire);
  std::uint64_t tail = tail_.load(std::memory_order_relaxed);
  while (tail < head) {
    const std::size_t at = std::size_t(tail % ring_.size());
    const std::size_t n = std::size_t(std::min<std::uint64_t>(head - tail, ring_.size() - at));
    const ssize_t written = ::write(fd_, ring_.data() + at, n);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) {
      error_ = errno;
      failed_.store(true, std::memory_order_relaxed);
      tail_.store(head,
                  std::memory_order_release);  // dropped: the producer must not wait on a dead file
      return false;
    }
    tail += std::uint64_t(written);
    tail_.store(tail, std::memory_order_release);
  }
  return true;
}

void StreamRecorder::writerLoop() {
  const auto period = std::chrono::duration<double>(options_.flushEveryS);
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, period, [this] { return stop_ || woken_; });
    woken_ = false;
    lock.unlock();
    drain();
    lock.lock();
  }
}

void StreamRecorder::close() {
  if (fd_ < 0) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  if (writer_.joinable()) writer_.join();
  drain();
  const bool closed = ::close(fd_) == 0;
  fd_ = -1;
  if (failed_.load() || !closed) {
    throw InputError(name_ + ": writing the recording failed (" +
                     std::strerror(error_ ? error_ : EIO) + ")");
  }
}

// ---- reading ----

namespace {

// Lines of a file with a bounded length, so a file that is one endless line cannot take the
// memory: a longer line is an error.
class LineReader {
 public:
  static constexpr std::size_t kMaxLine = 1024;
  explicit LineReader(const std::string& path)
      : file_(std::fopen(path.c_str(), "rb"), &std::fclose) {}
  bool open() const { return file_ != nullptr; }
  // false at the end of the file; `tooLong` when the line passed kMaxLine bytes.
  bool next(std::string& line, bool& tooLong) {
    line.clear();
    tooLong = false;
    int c = 0;
    bool any = false;
    while ((c = std::getc(file_.get())) != EOF) {
      any = true;
      if (c == '\n') break;
      if (line.size() < kMaxLine) {
        line.push_back(char(c));
      } else {
        tooLong = true;
      }
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return any;
  }

 private:
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
};

std::string trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return std::string(s);
}

// Parses a whole field as a double (nan, inf allowed); false for anything else.
bool parseDouble(const std::string& field, double& value) {
  const char* begin = field.data();
  const char* end = field.data() + field.size();
  if (begin != end && *begin == '+') ++begin;
  if (begin == end) return false;
  const std::from_chars_result r = std::from_chars(begin, end, value);
  return r.ec == std::errc() && r.ptr == end;
}

std::string shortNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

Recording loadRecording(const std::string& path) {
  requireRegularFile(path, "the recording");
  LineReader reader(path);
  if (!reader.open())
    throw InputError(path + ": cannot open the recording (" + std::strerror(errno) + ")");
  Recording recording;
  recording.path = path;
  std::string line;
  bool tooLong = false;
  const std::string notRecording =
      ": not a device recording (expected the header " + std::string(kRecordingHeader) + ")";
  if (!reader.next(line, tooLong)) throw InputError(path + ": empty file" + notRecording);
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 byte order mark
  std::string header;
  for (char c : line) {
    if (c != ' ' && c != '\t') header.push_back(c);
  }
  const bool withSettings = header == kRecordingHeader;
  if (tooLong || (!withSettings && header != kRecordingHeaderWithoutSettings))
    throw InputError(path + ":1" + notRecording);
  const std::size_t columns = withSettings ? 13 : 11;

  static const char* const kNames[13] = {"t",        "x",   "y",         "z",       "qw",
                                         "qx",       "qy",  "qz",        "buttons", "pedal",
                                         "drill_on", "rpm", "irrigation"};
  std::size_t lineNo = 1;
  std::vector<std::string> fields;
  while (reader.next(line, tooLong)) {
    ++lineNo;
    const std::string where = path + ":" + std::to_string(lineNo);
    if (tooLong)
      throw InputError(where + ": line longer than " + std::to_string(LineReader::kMaxLine) +
                       " bytes");
    if (trim(line).empty()) continue;
    fields.clear();
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      fields.push_back(trim(std::string_view(line).substr(
          start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (fields.size() != columns) {
      throw InputError(where + ": expected " + std::to_string(columns) + " fields (" + header +
                       "), found " + std::to_string(fields.size()));
    }
    double v[13] = {};
    for (int i = 0; i < int(columns); ++i) {
      if (!parseDouble(fields[std::size_t(i)], v[i])) {
        throw InputError(where + ": " + kNames[i] + " '" + fields[std::size_t(i)].substr(0, 40) +
                         "' is not a number");
      }
    }
    RecordingRow row;
    row.tS = v[0];
    if (!std::isfinite(row.tS) || row.tS < 0.0)
      throw InputError(where + ": t must be a finite time >= 0 s");
    if (!recording.rows.empty()) {
      const double previous = recording.rows.back().tS;
      if (!(row.tS > previous)) {
        throw InputError(where + ": t=" + shortNumber(row.tS) +
                         " is not after the previous row's " + shortNumber(previous));
      }
      if (row.tS - recording.rows.front().tS > kMaxRecordingS) {
        throw InputError(where + ": t=" + shortNumber(row.tS) + ": a recording lasts at most " +
                         shortNumber(kMaxRecordingS) + " s");
      }
    }
    if (recording.rows.size() >= kMaxRecordingRows) {
      throw InputError(where + ": more than " + std::to_string(kMaxRecordingRows) + " rows");
    }
    // Non-finite pose values are device faults, kept for the safety layer.
    row.positionMm = glm::dvec3(v[1], v[2], v[3]);
    row.orientation = glm::dquat(v[4], v[5], v[6], v[7]);
    if (!(v[8] >= 0.0 && v[8] <= 4294967295.0 && v[8] == std::floor(v[8]))) {
      throw InputError(where + ": buttons must be an integer mask 0..4294967295");
    }
    row.buttons = std::uint32_t(v[8]);
    if (!(v[9] >= 0.0 && v[9] <= 1.0)) throw InputError(where + ": pedal must be a number in 0..1");
    row.pedal = v[9];
    if (!(v[10] == 0.0 || v[10] == 1.0)) throw InputError(where + ": drill_on must be 0 or 1");
    row.drillOn = v[10] == 1.0;
    if (withSettings) {
      if (!(v[11] == 0.0 || (v[11] >= 100.0 && v[11] <= 100000.0)))
        throw InputError(where + ": rpm must be 0 (not recorded) or 100..100000");
      if (!(v[12] == 0.0 || v[12] == 1.0)) throw InputError(where + ": irrigation must be 0 or 1");
      row.rpm = v[11];
      row.irrigation = v[12] == 1.0;
    }
    recording.rows.push_back(row);
  }
  if (recording.rows.empty()) throw InputError(path + ": no rows after the header");
  recording.rows.shrink_to_fit();
  return recording;
}

ReplayDevice::ReplayDevice(const std::string& name, Recording recording)
    : Device(name), recording_(std::move(recording)) {}

Capabilities ReplayDevice::capabilities() const {
  Capabilities c;
  c.pose = true;
  c.buttons = true;
  c.pedal = true;
  c.timeDriven = true;
  c.recorded = true;
  c.worldFrame = true;
  c.startS = recording_.startS();
  c.endS = recording_.endS();
  return c;
}

void ReplayDevice::poll(double nowS, DeviceSample& sample) noexcept {
  const std::vector<RecordingRow>& rows = recording_.rows;
  const double t = nowS + 1e-9;  // a row stamped at the tick belongs to it despite rounding
  if (next_ > 0 && rows[next_ - 1].tS > t) {
    // Time went back (a restart): find the place again.
    next_ = std::size_t(std::upper_bound(rows.begin(), rows.end(), t,
                                         [](double v, const RecordingRow& r) { return v < r.tS; }) -
                        rows.begin());
  }
  while (next_ < rows.size() && rows[next_].tS <= t) ++next_;
  if (next_ == 0) {
    sample = DeviceSample{};
    return;
  }
  const RecordingRow& r = rows[next_ - 1];
  sample.tS = r.tS;
  sample.positionMm = r.positionMm;
  sample.orientation = r.orientation;
  sample.buttons = r.buttons;
  sample.pedal = r.pedal;
  sample.drillOn = r.drillOn;
  sample.rpm = r.rpm;
  sample.irrigation = r.irrigation;
  sample.connected = true;
}

}  // namespace osteon::devices
