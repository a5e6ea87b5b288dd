// libFuzzer: the device-recording CSV parser, as `osteon replay FILE.csv MESH` reads it.
#include "fuzz_input.h"
#include "osteon/devices/recording.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return osteon::fuzz::runOnFile(
      data, size, ".csv", [](const std::string& path) { osteon::devices::loadRecording(path); });
}
