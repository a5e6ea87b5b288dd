// libFuzzer: the validate report reader, as `osteon validate --compare OLD.json` and
// `osteon validate --merge DIR...` read a report.json (both checks on every input).
#include "fuzz_input.h"
#include "report_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  osteon::fuzz::runOnFile(data, size, ".json",
                          [](const std::string& path) { osteon::cli::readComparable(path); });
  return osteon::fuzz::runOnFile(
      data, size, ".json", [](const std::string& path) { osteon::cli::readShard("shard", path); });
}
