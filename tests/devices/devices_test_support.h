// Small helpers for the devices suite, which links osteon::devices alone (no geometry, so not
// tests/support): scratch folders, files, pseudo-terminals standing in for serial boards.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

namespace osteon::devices::test {

inline std::string makeTempDir(const std::string& tag) {
  static std::atomic<int> counter{0};
  std::ostringstream name;
  name << "osteon_devices_" << tag << "_" << ::getpid() << "_" << counter++;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name.str();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

inline void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A pseudo-terminal as a simulated serial device: the test writes the board's bytes to the
// master; the code under test opens the slave by name. The slave is raw (no CR/LF
// translation, no echo), as a USB serial port is.
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
  bool write(const std::string& bytes, int timeoutMs = 10000) const {
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
  ~FakeBoard() { unplug(); }
};

// Points `link` at `target` atomically (as udev's /dev/serial/by-id names follow a board).
inline void pointLink(const std::string& link, const std::string& target) {
  const std::string tmp = link + ".new";
  std::filesystem::remove(tmp);
  std::filesystem::create_symlink(target, tmp);
  std::filesystem::rename(tmp, link);
}

}  // namespace osteon::devices::test
