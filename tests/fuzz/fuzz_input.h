// libFuzzer harness shared by every loader target: the input goes to a file of the loader's
// extension on a RAM disk (osteon's loaders read files, as users give them), then to the
// loader. An InputError is a right answer; anything else (another exception, a crash, a
// sanitizer report, a hang, an allocation past -rss_limit_mb) is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fcntl.h>
#include <string>
#include <unistd.h>

#include "osteon/core/error.h"

namespace osteon::fuzz {

// One file per process, reused for every input.
inline const std::string& inputPath(const char* extension) {
  static const std::string path = [extension] {
    const char* dir = std::getenv("OSTEON_FUZZ_DIR");
    return std::string(dir ? dir : "/dev/shm") + "/osteon_fuzz_" + std::to_string(::getpid()) +
           extension;
  }();
  return path;
}

template <typename Load>
int runOnFile(const std::uint8_t* data, std::size_t size, const char* extension, Load load) {
  const std::string& path = inputPath(extension);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  if (fd < 0) std::abort();
  for (std::size_t done = 0; done < size;) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n <= 0) std::abort();
    done += std::size_t(n);
  }
  ::close(fd);
  try {
    load(path);
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace osteon::fuzz
