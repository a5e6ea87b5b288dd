// The one reader of OpenIGTLink streams (protocol 2 headers, 58 bytes): what comes off the
// network, from a client of the server or from a tracker, goes through it. A message of a type
// not asked for is skipped as it streams past, whatever its size, and never kept; one asked for
// whose body is over the limit breaks the stream before anything is allocated for it; one whose
// CRC does not match is skipped. Each is counted. It never throws on bad bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace osteon::devices {

inline constexpr std::size_t kIgtlHeaderBytes = 58;

struct IgtlMessage {
  std::string type;  // "TRANSFORM", "GET_POLYDATA", ...
  std::string name;  // the device name
  std::uint16_t version = 0;
  std::uint64_t timestamp = 0;  // 32.32 fixed-point seconds, as sent
  std::vector<std::uint8_t> body;
};

struct IgtlReaderStats {
  std::uint64_t messages = 0;   // complete, checked and of a type asked for
  std::uint64_t skipped = 0;    // of other types
  std::uint64_t crcErrors = 0;  // skipped: the body's CRC-64 is not the header's
};

class IgtlStreamReader {
 public:
  // types: the message types kept (empty: all); maxBodyBytes: the largest body accepted.
  explicit IgtlStreamReader(std::vector<std::string> types = {},
                            std::size_t maxBodyBytes = std::size_t(64) << 20);
  // Takes bytes as they arrive. Returns false once the stream is broken (a body over the
  // limit): nothing after it can be framed, the connection is to be closed.
  bool feed(const std::uint8_t* data, std::size_t size);
  // The next complete message, if any.
  bool next(IgtlMessage& out);
  bool broken() const { return !broken_.empty(); }
  const std::string& brokenReason() const { return broken_; }
  const IgtlReaderStats& stats() const { return stats_; }

 private:
  std::vector<std::string> types_;
  std::size_t maxBodyBytes_;
  std::vector<std::uint8_t> pending_;
  std::size_t start_ = 0;        // first unread byte of pending_
  std::uint64_t skipBytes_ = 0;  // of a skipped body, still to come (dropped by feed)
  void compact();
  std::string broken_;
  IgtlReaderStats stats_;
};

// A TRANSFORM body (12 big-endian float32: the rotation's columns, then the translation) as a
// 4x4 matrix; false for a body of another size or with values that are not finite.
bool decodeIgtlTransform(const IgtlMessage& message, glm::dmat4& out);

// A tracked tool's pose from a TRANSFORM named `name`, or from the element named `name` of a
// TDATA (70-byte elements: name, type, reserved, a TRANSFORM's 12 floats) or QTDATA (50-byte
// elements: name, type, reserved, position, quaternion x y z w); an empty `name` takes any
// (the first element). False when there is none, or it is malformed or not finite.
bool decodeIgtlPose(const IgtlMessage& message, const std::string& name, glm::dmat4& out);

}  // namespace osteon::devices
