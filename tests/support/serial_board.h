// A pseudo-terminal standing in for a USB serial board (a button board, a foot pedal): the test
// writes the board's bytes to the master; the code under test opens the slave by name. The
// slave is raw (no CR/LF translation, no echo), as a USB serial port is. Header-only and POSIX
// alone, for the devices suite and the command-line tests alike.
#pragma once

#include <chrono>
#include <fcntl.h>
#include <filesystem>
#include <poll.h>
#include <pty.h>
#include <string>
#include <termios.h>
#include <unistd.h>

namespace osteon::test {

struct FakeBoard {
  int master = -1;
  int slave = -1;
  std::string slavePath;

  bool open() {
    char name[128] = {};
    if (::openpty(&master, &slave, name, nullptr, nullptr) != 0) return false;
    termios t{};
    ::tcgetattr(slave, &t);
    ::cfmakeraw(&t);
    ::tcsetattr(slave, TCSANOW, &t);
    ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
    slavePath = name;
    return true;
  }
  // Writes every byte within timeoutMs (the reader drains the pty's small buffer as it goes).
  bool write(const std::string& bytes, int timeoutMs = 20000) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(master, bytes.data() + done, bytes.size() - done);
      if (n > 0) {
        done += std::size_t(n);
        continue;
      }
      if (std::chrono::steady_clock::now() > deadline) return false;
      pollfd p{master, POLLOUT, 0};
      ::poll(&p, 1, 20);
    }
    return true;
  }
  // The board is unplugged: both ends go, and the slave's name with them.
  void unplug() {
    if (master >= 0) ::close(master);
    if (slave >= 0) ::close(slave);
    master = slave = -1;
  }
  FakeBoard() = default;
  FakeBoard(const FakeBoard&) = delete;
  FakeBoard& operator=(const FakeBoard&) = delete;
  ~FakeBoard() { unplug(); }
};

// Points `link` at `target` atomically (as udev's /dev/serial/by-id names follow a board).
inline void pointLink(const std::string& link, const std::string& target) {
  const std::string tmp = link + ".new";
  std::filesystem::remove(tmp);
  std::filesystem::create_symlink(target, tmp);
  std::filesystem::rename(tmp, link);
}

}  // namespace osteon::test
