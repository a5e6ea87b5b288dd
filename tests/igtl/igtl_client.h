// A client of osteon's OpenIGTLink server written with the reference library alone (its
// ClientSocket and message classes): what Slicer's OpenIGTLinkIF does with the stream, kept.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace osteon::test {

struct ReceivedTransform {
  glm::dmat4 matrix{1.0};
  double latencyS = 0.0;  // receive time - the header's time stamp
};

struct IgtlReceived {
  glm::ivec3 dims{0};
  std::vector<std::uint8_t> volume;  // the IMAGE Bone messages applied in order (uint8 fill)
  int wholeVolumes = 0, subVolumes = 0;
  float spacing[3] = {0, 0, 0};
  std::vector<ReceivedTransform> transforms;
  std::vector<std::string> strings;   // "name=value"
  std::vector<std::string> polydata;  // names
  std::uint64_t messages = 0, bytes = 0;
  std::vector<double> latenciesS;    // every message
  double firstS = 0.0, lastS = 0.0;  // receive times
};

// Connects (retrying for 30 s), then reads until the server closes the connection.
// getPolyData: sends GET_POLYDATA once connected.
IgtlReceived receiveAll(int port, bool getPolyData = false);

}  // namespace osteon::test
