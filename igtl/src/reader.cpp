#include "osteon/igtl/reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "igtl_util.h"

namespace osteon::igtl {

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

}  // namespace

StreamReader::StreamReader(std::vector<std::string> types, std::size_t maxBodyBytes)
    : types_(std::move(types)), maxBodyBytes_(maxBodyBytes) {}

bool StreamReader::feed(const std::uint8_t* data, std::size_t size) {
  if (broken()) return false;
  if (start_ > 0 && start_ == pending_.size()) {
    pending_.clear();
    start_ = 0;
  }
  pending_.insert(pending_.end(), data, data + size);
  return true;
}

bool StreamReader::next(Message& out) {
  while (!broken()) {
    const std::size_t available = pending_.size() - start_;
    if (available < kHeaderBytes) return false;
    const std::uint8_t* h = pending_.data() + start_;
    const std::uint64_t bodyBytes = bigEndian(h + 42, 8);
    // Checked before anything is allocated for it: a hostile header cannot ask for memory.
    if (bodyBytes > maxBodyBytes_) {
      broken_ = "a message body of " + std::to_string(bodyBytes) + " bytes, over the limit of " +
                std::to_string(maxBodyBytes_);
      return false;
    }
    const std::size_t total = kHeaderBytes + static_cast<std::size_t>(bodyBytes);
    if (available < total) return false;
    const std::string type = field(h + 2, 12);
    const std::uint8_t* body = h + kHeaderBytes;
    const bool wanted =
        types_.empty() || std::find(types_.begin(), types_.end(), type) != types_.end();
    bool crcOk = true;
    if (wanted) {
      const std::uint64_t crc = crc64(const_cast<unsigned char*>(body), bodyBytes, 0ULL);
      crcOk = crc == bigEndian(h + 50, 8);
    }
    if (wanted && crcOk) {
      out.version = static_cast<std::uint16_t>(bigEndian(h, 2));
      out.type = type;
      out.name = field(h + 14, 20);
      out.timestamp = bigEndian(h + 34, 8);
      out.body.assign(body, body + bodyBytes);
    }
    start_ += total;
    if (start_ == pending_.size()) {
      pending_.clear();
      start_ = 0;
    } else if (start_ > (std::size_t(1) << 20)) {  // keep the buffer from creeping
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(start_));
      start_ = 0;
    }
    if (!wanted) {
      ++stats_.skipped;
    } else if (!crcOk) {
      ++stats_.crcErrors;
    } else {
      ++stats_.messages;
      return true;
    }
  }
  return false;
}

bool decodeTransform(const Message& message, glm::dmat4& out) {
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

}  // namespace osteon::igtl
