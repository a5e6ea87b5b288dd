// What every loader checks before it opens a name: that it is a regular file. A directory, a
// FIFO or a device (/dev/zero) would otherwise be read as an empty, blocking or endless file.
#pragma once

#include <cerrno>
#include <string>
#include <sys/stat.h>
#include <system_error>

#include "osteon/core/error.h"

namespace osteon {

// A file name as messages show it: a NUL byte (which would end the name the system sees) as \0.
inline std::string printableFileName(const std::string& path) {
  std::string out;
  for (const char c : path) {
    if (c == '\0') {
      out += "\\0";
    } else {
      out += c;
    }
  }
  return out;
}

// Why `path` cannot be opened as a regular file: "" when it can be, else the reason as the
// system gives it (a name with a NUL byte is refused before the system would cut it short).
inline std::string inputFileProblem(const std::string& path) {
  if (path.find('\0') != std::string::npos) return "the file name contains a NUL byte";
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) {
    switch (errno) {
      case ENOENT:
        return "no such file";
      case ELOOP:
        return "too many levels of symbolic links";
      case ENOTDIR:
        return "no such file: a part of the path is not a folder";
      case EACCES:
        return "permission denied: a folder on the path cannot be searched";
      default:
        return std::generic_category().message(errno);
    }
  }
  if (S_ISREG(s.st_mode)) return "";
  const char* kind = S_ISDIR(s.st_mode)    ? "a directory"
                     : S_ISFIFO(s.st_mode) ? "a pipe"
                     : S_ISCHR(s.st_mode)  ? "a character device"
                     : S_ISBLK(s.st_mode)  ? "a block device"
                     : S_ISSOCK(s.st_mode) ? "a socket"
                                           : "not a file";
  return std::string("not a regular file (") + kind + ")";
}

// Every loader's first check of a name: throws InputError "<path>: no such file", "<path>: too
// many levels of symbolic links (a link loop)", "<path>: not a regular file (a directory)", ...
inline void requireInputFile(const std::string& path) {
  const std::string problem = inputFileProblem(path);
  if (!problem.empty()) throw InputError(printableFileName(path) + ": " + problem);
}

// Throws InputError "<path>: cannot open <what> (no such file)" or
// "<path>: not a regular file (a directory)".
inline void requireRegularFile(const std::string& path, const std::string& what = "it") {
  const std::string problem = inputFileProblem(path);
  if (problem.empty()) return;
  if (problem.rfind("not a regular file", 0) == 0)
    throw InputError(printableFileName(path) + ": " + problem);
  throw InputError(printableFileName(path) + ": cannot open " + what + " (" + problem + ")");
}

}  // namespace osteon
