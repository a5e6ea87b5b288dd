// libFuzzer: the OpenIGTLink stream reader, as the igtl: device and the server's requests read
// what comes off the network. The first byte picks how the rest is split into reads.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "osteon/devices/igtl_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = std::size_t(data[0]) * 7 + 1;
  osteon::devices::IgtlStreamReader reader({}, std::size_t(1) << 16);
  osteon::devices::IgtlMessage m;
  glm::dmat4 t;
  for (std::size_t at = 1; at < size; at += chunk) {
    if (!reader.feed(data + at, std::min(chunk, size - at))) break;
    while (reader.next(m)) {
      osteon::devices::decodeIgtlTransform(m, t);
      osteon::devices::decodeIgtlPose(m, "", t);
      osteon::devices::decodeIgtlPose(m, "Stylus", t);
    }
  }
  return 0;
}
