// What every loader checks before it opens a name: that it is a regular file. A directory, a
// FIFO or a device (/dev/zero) would otherwise be read as an empty, blocking or endless file.
#pragma once

#include "osteon/core/error.h"

#include <string>
#include <system_error>

#include <sys/stat.h>

namespace osteon {

// Throws InputError "<path>: cannot open <what> (No such file or directory)" or
// "<path>: not a regular file (a directory)".
inline void requireRegularFile(const std::string& path, const std::string& what = "it") {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) {
    throw InputError(path + ": cannot open " + what + " (" + std::generic_category().message(errno) + ")");
  }
  if (S_ISREG(s.st_mode)) return;
  const char* kind = S_ISDIR(s.st_mode)    ? "a directory"
                     : S_ISFIFO(s.st_mode) ? "a pipe"
                     : S_ISCHR(s.st_mode)  ? "a character device"
                     : S_ISBLK(s.st_mode)  ? "a block device"
                     : S_ISSOCK(s.st_mode) ? "a socket"
                                           : "not a file";
  throw InputError(path + ": not a regular file (" + kind + ")");
}

}  // namespace osteon
