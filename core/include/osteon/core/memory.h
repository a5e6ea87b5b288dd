// The memory a request may use: requests whose estimate exceeds what this machine (or the
// process's address-space limit) has are refused up front, with the estimate, instead of
// failing halfway through an allocation or being killed by the kernel.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <sys/resource.h>
#include <unistd.h>

#include "osteon/core/error.h"

namespace osteon {

// Physical memory, or the address-space limit (`ulimit -v`) when that is lower.
inline std::uint64_t machineMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long pageBytes = ::sysconf(_SC_PAGE_SIZE);
  std::uint64_t bytes =
      pages > 0 && pageBytes > 0 ? std::uint64_t(pages) * std::uint64_t(pageBytes) : UINT64_MAX;
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    bytes = std::min<std::uint64_t>(bytes, limit.rlim_cur);
  }
  return bytes;
}

// The process's peak resident set so far, in MB (2^20 bytes; getrusage's ru_maxrss, which Linux
// gives in KiB): what set-up really cost in memory, beside the estimates above. 0 if unknown.
inline double peakRssMb() {
  rusage usage{};
  if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return double(usage.ru_maxrss) / 1024.0;
}

// Returns the heap's free pages to the system (glibc keeps what large structures freed, in
// every thread's arena): after a big structure is dropped, so the next one's pages are not
// counted on top of it in the peak.
inline void giveBackFreedMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

// "12.3 GB", "850 MB".
inline std::string memoryText(double bytes) {
  char text[32];
  if (bytes >= 1e12) {
    std::snprintf(text, sizeof text, "%.3g TB", bytes / 1e12);
  } else if (bytes >= 1e9) {
    std::snprintf(text, sizeof text, "%.3g GB", bytes / 1e9);
  } else {
    std::snprintf(text, sizeof text, "%.3g MB", bytes / 1e6);
  }
  return text;
}

// Throws InputError "<what> would need about X of memory, more than this machine's Y; <advice>".
inline void refuseOverMemory(const std::string& what, double estimateBytes,
                             const std::string& advice) {
  const double available = double(machineMemoryBytes());
  if (!(estimateBytes > available)) return;
  throw InputError(what + " would need about " + memoryText(estimateBytes) +
                   " of memory, more than this machine's " + memoryText(available) +
                   (advice.empty() ? "" : "; " + advice));
}

}  // namespace osteon
