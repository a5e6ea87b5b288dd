#include "osteon/devices/igtl_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <glm/gtc/quaternion.hpp>

namespace osteon::devices {

namespace {

std::uint64_t bigEndian(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}

// A fixed-width, NUL-padded text field (not always NUL-terminated).
std::string field(const std::uint8_t* p, std::size_t width) {
  std::size_t n = 0;
  while (n < width && p[n] != 0) ++n;
  return std::string(reinterpret_cast<const char*>(p), n);
}

// CRC-64 as OpenIGTLink computes it (ECMA-182 polynomial, MSB first, no reflection, initial and
// final value 0): written here so that devices needs no OpenIGTLink.
std::uint64_t crc64(const std::uint8_t* data, std::uint64_t size) {
  static const auto table = [] {
    std::array<std::uint64_t, 256> t{};
    for (std::uint64_t i = 0; i < 256; ++i) {
      std::uint64_t c = i << 56;
      for (int b = 0; b < 8; ++b)
        c = (c & (1ULL << 63)) ? (c << 1) ^ 0x42F0E1EBA9EA3693ULL : c << 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint64_t crc = 0;
  for (std::uint64_t i = 0; i < size; ++i) crc = table[((crc >> 56) ^ data[i]) & 0xFF] ^ (crc << 8);
  return crc;
}

}  // namespace

IgtlStreamReader::IgtlStreamReader(std::vector<std::string> types, std::size_t maxBodyBytes)
    : types_(std::move(types)), maxBodyBytes_(maxBodyBytes) {}

bool IgtlStreamReader::feed(const std::uint8_t* data, std::size_t size) {
  if (broken()) return false;
  if (start_ > 0 && start_ == pending_.size()) {
    pending_.clear();
    start_ = 0;
  }
  // The rest of a body of a type not asked for is dropped as it comes, never kept.
  const std::size_t skip = static_cast<std::size_t>(std::min<std::uint64_t>(skipBytes_, size));
  skipBytes_ -= skip;
  pending_.insert(pending_.end(), data + skip, data + size);
  return true;
}

void IgtlStreamReader::compact() {
  if (start_ == pending_.size()) {
    pending_.clear();
    start_ = 0;
  } else if (start_ > (std::size_t(1) << 20)) {  // keep the buffer from creeping
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
}

bool IgtlStreamReader::next(IgtlMessage& out) {
  while (!broken()) {
    const std::size_t available = pending_.size() - start_;
    if (available < kIgtlHeaderBytes) return false;
    const std::uint8_t* h = pending_.data() + start_;
    const std::uint64_t bodyBytes = bigEndian(h + 42, 8);
    const std::string type = field(h + 2, 12);
    const bool wanted =
        types_.empty() || std::find(types_.begin(), types_.end(), type) != types_.end();
    if (!wanted) {  // skipped whatever its size: what is here now, the rest as it comes
      const std::uint64_t here = std::min<std::uint64_t>(bodyBytes, available - kIgtlHeaderBytes);
      start_ += kIgtlHeaderBytes + static_cast<std::size_t>(here);
      skipBytes_ = bodyBytes - here;
      ++stats_.skipped;
      compact();
      continue;
    }
    // Checked before anything is allocated for it: a hostile header cannot ask for memory.
    if (bodyBytes > maxBodyBytes_) {
      broken_ = "a message body of " + std::to_string(bodyBytes) + " bytes, over the limit of " +
                std::to_string(maxBodyBytes_);
      return false;
    }
    const std::size_t total = kIgtlHeaderBytes + static_cast<std::size_t>(bodyBytes);
    if (available < total) return false;
    const std::uint8_t* body = h + kIgtlHeaderBytes;
    const bool crcOk = crc64(body, bodyBytes) == bigEndian(h + 50, 8);
    if (crcOk) {
      out.version = static_cast<std::uint16_t>(bigEndian(h, 2));
      out.type = type;
      out.name = field(h + 14, 20);
      out.timestamp = bigEndian(h + 34, 8);
      out.body.assign(body, body + bodyBytes);
    }
    start_ += total;
    compact();
    if (!crcOk) {
      ++stats_.crcErrors;
    } else {
      ++stats_.messages;
      return true;
    }
  }
  return false;
}

bool decodeIgtlTransform(const IgtlMessage& message, glm::dmat4& out) {
  if (message.body.size() != 48) return false;
  float v[12];
  for (int i = 0; i < 12; ++i) {
    const auto bits = static_cast<std::uint32_t>(
        bigEndian(message.body.data() + 4 * static_cast<std::size_t>(i), 4));
    std::memcpy(&v[i], &bits, sizeof bits);
    if (!std::isfinite(v[i])) return false;
  }
  out = glm::dmat4(1.0);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 3; ++r) out[c][r] = double(v[3 * c + r]);
  }
  return true;
}

namespace {

bool floatsAt(const std::uint8_t* p, int count, float* out) {
  for (int i = 0; i < count; ++i) {
    const auto bits = static_cast<std::uint32_t>(bigEndian(p + 4 * i, 4));
    std::memcpy(&out[i], &bits, sizeof bits);
    if (!std::isfinite(out[i])) return false;
  }
  return true;
}

}  // namespace

bool decodeIgtlPose(const IgtlMessage& message, const std::string& name, glm::dmat4& out) {
  if (message.type == "TRANSFORM")
    return (name.empty() || message.name == name) && decodeIgtlTransform(message, out);
  const bool quaternion = message.type == "QTDATA";
  if (!quaternion && message.type != "TDATA") return false;
  const std::size_t elementBytes = quaternion ? 50 : 70;
  const std::vector<std::uint8_t>& b = message.body;
  if (b.empty() || b.size() % elementBytes != 0) return false;
  for (std::size_t at = 0; at < b.size(); at += elementBytes) {
    if (!name.empty() && field(b.data() + at, 20) != name) continue;
    float v[12];
    out = glm::dmat4(1.0);
    if (quaternion) {
      if (!floatsAt(b.data() + at + 22, 7, v)) return false;
      const glm::dquat q{static_cast<double>(v[6]), static_cast<double>(v[3]),
                         static_cast<double>(v[4]), static_cast<double>(v[5])};
      if (!(glm::length(q) > 0.5)) return false;
      out = glm::dmat4(glm::mat3_cast(glm::normalize(q)));
      out[3] = glm::dvec4(double(v[0]), double(v[1]), double(v[2]), 1.0);
      return true;
    }
    if (!floatsAt(b.data() + at + 22, 12, v)) return false;
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 3; ++r) out[c][r] = double(v[3 * c + r]);
    }
    return true;
  }
  return false;
}

}  // namespace osteon::devices
