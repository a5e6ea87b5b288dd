#include "osteon/audio/wav_writer.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <unistd.h>

#include "osteon/core/error.h"

namespace osteon::audio {

namespace {

void put32(std::uint8_t* at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) at[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void put16(std::uint8_t* at, std::uint16_t v) {
  at[0] = static_cast<std::uint8_t>(v);
  at[1] = static_cast<std::uint8_t>(v >> 8);
}

// All of `bytes` at `offset` (or appended when offset < 0); false with errno set otherwise.
bool writeAll(int fd, const void* data, std::size_t bytes, off_t offset = -1) {
  const char* p = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t n = offset < 0 ? ::write(fd, p, bytes) : ::pwrite(fd, p, bytes, offset);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += n;
    bytes -= static_cast<std::size_t>(n);
    if (offset >= 0) offset += n;
  }
  return true;
}

}  // namespace

std::array<std::uint8_t, 44> wavHeader(std::uint32_t sampleRateHz, std::uint32_t samples) {
  std::array<std::uint8_t, 44> h{};
  const std::uint32_t dataBytes = samples * 2;
  std::memcpy(h.data(), "RIFF", 4);
  put32(h.data() + 4, 36 + dataBytes);
  std::memcpy(h.data() + 8, "WAVEfmt ", 8);
  put32(h.data() + 16, 16);  // the fmt chunk's size
  put16(h.data() + 20, 1);   // PCM
  put16(h.data() + 22, 1);   // mono
  put32(h.data() + 24, sampleRateHz);
  put32(h.data() + 28, sampleRateHz * 2);  // bytes per second
  put16(h.data() + 32, 2);                 // bytes per frame
  put16(h.data() + 34, 16);                // bits per sample
  std::memcpy(h.data() + 36, "data", 4);
  put32(h.data() + 40, dataBytes);
  return h;
}

WavWriter::WavWriter(const std::string& path, std::uint32_t sampleRateHz)
    : path_(path), rateHz_(sampleRateHz) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(path + ": cannot write (" + std::strerror(errno) + ")");
  const auto header = wavHeader(rateHz_, 0);  // its sizes are written by finish()
  if (!writeAll(fd_, header.data(), header.size())) error_ = errno;
}

WavWriter::~WavWriter() {
  if (fd_ >= 0) ::close(fd_);
}

void WavWriter::write(const float* samples, std::size_t n) noexcept {
  for (std::size_t i = 0; i < n; ++i) {
    const double x = std::clamp(static_cast<double>(samples[i]), -1.0, 1.0);
    buffer_[used_++] = static_cast<std::int16_t>(std::lround(x * 32767.0));
    if (used_ == buffer_.size()) flush();
  }
  samples_ += n;
}

void WavWriter::flush() noexcept {
  if (used_ == 0) return;
  // Little-endian 16-bit samples, as WAV stores them, whatever the machine's order.
  std::array<std::uint8_t, sizeof(buffer_)> bytes{};
  for (std::size_t i = 0; i < used_; ++i)
    put16(bytes.data() + 2 * i, static_cast<std::uint16_t>(buffer_[i]));
  if (error_ == 0 && !writeAll(fd_, bytes.data(), used_ * 2)) error_ = errno;
  used_ = 0;
}

void WavWriter::finish() {
  flush();
  if (samples_ > 0x7fffffffULL) error_ = EFBIG;  // past a WAV's 32-bit sizes
  const auto header = wavHeader(
      rateHz_, static_cast<std::uint32_t>(std::min<std::uint64_t>(samples_, 0x7fffffffULL)));
  if (error_ == 0 && !writeAll(fd_, header.data(), header.size(), 0)) error_ = errno;
  if (error_ == 0 && ::fsync(fd_) != 0) error_ = errno;
  if (::close(fd_) != 0 && error_ == 0) error_ = errno;
  fd_ = -1;
  if (error_ != 0)
    throw InputError(path_ + ": cannot write the sound (" + std::strerror(error_) + ")");
}

WavRecording::WavRecording(const std::string& path)
    : wav_(path, static_cast<std::uint32_t>(kSampleRateHz)) {}

void WavRecording::add(const SoundFrame& frame) noexcept {
  // The samples that end at this frame's time are rendered towards it, in blocks.
  sound_.setTarget(frame);
  const double t = std::isfinite(frame.tS) ? std::max(0.0, frame.tS) : 0.0;
  const auto due = static_cast<std::uint64_t>(std::llround(t * kSampleRateHz));
  std::array<float, 256> block{};
  while (rendered_ < due) {
    const std::size_t n =
        static_cast<std::size_t>(std::min<std::uint64_t>(block.size(), due - rendered_));
    sound_.render(block.data(), n);
    wav_.write(block.data(), n);
    rendered_ += n;
  }
}

void WavRecording::finish() {
  wav_.finish();
}

}  // namespace osteon::audio
