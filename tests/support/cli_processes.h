// `osteon` running beside a test (its stdout read line by line as it comes), with the fake
// serial board (serial_board.h): for tests of commands that watch a device.
#pragma once

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <poll.h>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>

#include "support/process.h"
#include "support/serial_board.h"

namespace osteon {

// `osteon ARGS...` running beside the test, its stdout read line by line as it comes.
class RunningOsteon {
 public:
  RunningOsteon(const std::vector<std::string>& args, const std::string& stderrPath) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    const int err = ::open(stderrPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    pid_ = test::spawnProgram(OSTEON_CLI, args, fds[1], err);
    ::close(err);
    ::close(fds[1]);
    out_ = fds[0];
  }
  ~RunningOsteon() {
    if (pid_ > 0 && exit_ < 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) ::close(out_);
  }
  // The next line of stdout, or "" when none came within timeoutMs (or the output ended).
  std::string nextLine(int timeoutMs = 10000) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
    while (true) {
      const std::size_t newline = buffer_.find('\n');
      if (newline != std::string::npos) {
        std::string line = buffer_.substr(0, newline);
        buffer_.erase(0, newline + 1);
        return line;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return "";
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, int(left.count())) <= 0) continue;
      char chunk[4096];
      const ssize_t n = ::read(out_, chunk, sizeof chunk);
      if (n <= 0) return "";
      buffer_.append(chunk, std::size_t(n));
    }
  }
  // The exit code, or -1 when it has not ended within timeoutMs (it is killed then).
  int waitExit(int timeoutMs = 10000) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) return -1;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    exit_ = test::exitCodeOf(status);
    return exit_;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  int exit_ = -1;
  std::string buffer_;
};

}  // namespace osteon
