// A serial port through POSIX termios: raw 8N1 at a standard baud rate, reads with a timeout.
// (libserialport cannot open a pseudo-terminal, which is how tests stand in for a board, so
// port I/O is ours; libserialport only lists USB ports, serial_list.cpp.)
#pragma once

#include <cstddef>
#include <string>

namespace osteon::devices {

class SerialPort {
 public:
  SerialPort() = default;
  ~SerialPort();
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // Opens `path` raw (no echo, no line editing, no CR/LF translation), 8 data bits, no parity,
  // one stop bit, no flow control, at `baud`. Throws InputError naming `name` (the path when
  // empty) and the reason.
  static SerialPort open(const std::string& path, int baud, const std::string& name = "");
  // The same, but returns a closed port instead of throwing (for reconnecting).
  static SerialPort tryOpen(const std::string& path, int baud) noexcept;

  bool isOpen() const { return fd_ >= 0; }
  // Up to `size` bytes: their count, 0 when nothing came within timeoutMs, -1 when the port is
  // gone (hung up, unplugged, closed); the port is then closed.
  int read(char* buf, std::size_t size, int timeoutMs) noexcept;
  // All of `size` bytes (blocking up to timeoutMs in total); false on failure or timeout.
  bool write(const char* data, std::size_t size, int timeoutMs) noexcept;
  void close() noexcept;

  // True for the baud rates termios has a constant for (50 .. 4000000).
  static bool supportedBaud(int baud);

 private:
  explicit SerialPort(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace osteon::devices
