// Programs run by tests, two ways: a shell command line with its outputs caught in files
// (runShell: limits and wrappers such as ulimit, timeout or xvfb-run are the command's own),
// and a program started directly (spawnProgram: no shell between, so the test can signal it,
// read its output as it comes or measure its own peak memory). Header-only, POSIX.
#pragma once

#include <chrono>
#include <cstdlib>
#include <fcntl.h>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "support/files.h"

namespace osteon::test {

// The exit code as a shell reports it: the program's own, or 128 + the signal that ended it.
inline int exitCodeOf(int waitStatus) {
  return WIFEXITED(waitStatus) ? WEXITSTATUS(waitStatus) : 128 + WTERMSIG(waitStatus);
}

struct ProcessRun {
  int exitCode = -1;
  std::string out;
  std::string err;
  double seconds = 0.0;  // wall time
};

// Runs `command` through /bin/sh with stdin from /dev/null and stdout and stderr into the two
// files (read back into the result).
inline ProcessRun runShell(const std::string& command, const std::string& outPath,
                           const std::string& errPath) {
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(
      ("( " + command + " ) >'" + outPath + "' 2>'" + errPath + "' </dev/null").c_str());
  ProcessRun run;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.exitCode = exitCodeOf(status);
  run.out = readBytes(outPath);
  run.err = readBytes(errPath);
  return run;
}

// Starts `program args...` with stdin from /dev/null, stdout and stderr on the given
// descriptors and no other descriptor of the test's (a pty held open here would never hang
// up); under an address-space limit when one is given. Returns the child's pid; the child
// exits 127 when the program cannot start. The caller closes its own copies of the descriptors.
inline pid_t spawnProgram(const std::string& program, const std::vector<std::string>& args,
                          int outFd, int errFd, rlim_t addressSpaceBytes = RLIM_INFINITY) {
  std::vector<char*> argv{const_cast<char*>(program.c_str())};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  const int null = ::open("/dev/null", O_RDONLY);
  ::dup2(null, 0);
  ::dup2(outFd, 1);
  ::dup2(errFd, 2);
  for (int fd = 3; fd < 1024; ++fd) ::close(fd);
  if (addressSpaceBytes != RLIM_INFINITY) {
    const rlimit limit{addressSpaceBytes, addressSpaceBytes};
    ::setrlimit(RLIMIT_AS, &limit);
  }
  ::execv(program.c_str(), argv.data());
  ::_exit(127);
}

}  // namespace osteon::test
