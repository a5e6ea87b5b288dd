#include "osteon/devices/serial_port.h"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>
#include <utility>

#include "osteon/core/error.h"

namespace osteon::devices {

namespace {

speed_t speedFor(int baud) {
  switch (baud) {
    case 50:
      return B50;
    case 75:
      return B75;
    case 110:
      return B110;
    case 134:
      return B134;
    case 150:
      return B150;
    case 200:
      return B200;
    case 300:
      return B300;
    case 600:
      return B600;
    case 1200:
      return B1200;
    case 1800:
      return B1800;
    case 2400:
      return B2400;
    case 4800:
      return B4800;
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 500000:
      return B500000;
    case 576000:
      return B576000;
    case 921600:
      return B921600;
    case 1000000:
      return B1000000;
    case 1152000:
      return B1152000;
    case 1500000:
      return B1500000;
    case 2000000:
      return B2000000;
    case 2500000:
      return B2500000;
    case 3000000:
      return B3000000;
    case 3500000:
      return B3500000;
    case 4000000:
      return B4000000;
    default:
      return B0;
  }
}

// Opens and configures; returns the fd or -1 with errno set.
int openRaw(const std::string& path, int baud) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return -1;
  termios tio{};
  if (::isatty(fd) == 0 || ::tcgetattr(fd, &tio) != 0) {
    const int e = errno == 0 ? ENOTTY : errno;
    ::close(fd);
    errno = e;
    return -1;
  }
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  const speed_t speed = speedFor(baud);
  if (::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0 ||
      ::tcsetattr(fd, TCSANOW, &tio) != 0) {
    const int e = errno;
    ::close(fd);
    errno = e;
    return -1;
  }
  return fd;
}

}  // namespace

bool SerialPort::supportedBaud(int baud) {
  return speedFor(baud) != B0;
}

SerialPort::~SerialPort() {
  close();
}

SerialPort::SerialPort(SerialPort&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

SerialPort SerialPort::open(const std::string& path, int baud, const std::string& name) {
  const std::string& who = name.empty() ? path : name;
  if (!supportedBaud(baud))
    throw InputError(who + ": baud rate " + std::to_string(baud) + " is not supported");
  const int fd = openRaw(path, baud);
  if (fd < 0) {
    const int e = errno;
    throw InputError(who + ": cannot open the serial port " + path + " (" +
                     std::string(std::strerror(e)) + ")");
  }
  return SerialPort(fd);
}

SerialPort SerialPort::tryOpen(const std::string& path, int baud) noexcept {
  if (!supportedBaud(baud)) return SerialPort();
  return SerialPort(openRaw(path, baud));
}

int SerialPort::read(char* buf, std::size_t size, int timeoutMs) noexcept {
  if (fd_ < 0) return -1;
  pollfd p{fd_, POLLIN, 0};
  int ready = 0;
  do {
    ready = ::poll(&p, 1, timeoutMs);
  } while (ready < 0 && errno == EINTR);
  if (ready < 0) {
    close();
    return -1;
  }
  if (ready == 0) return 0;
  // Data first: a board that hung up may have left lines behind.
  const ssize_t n = ::read(fd_, buf, size);
  if (n > 0) return int(n);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  // End of file with data promised, an error or a hang-up: the port is gone (the reader
  // opens it again when it returns).
  close();
  return -1;
}

bool SerialPort::write(const char* data, std::size_t size, int timeoutMs) noexcept {
  if (fd_ < 0) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeoutMs);
  while (size > 0) {
    const ssize_t n = ::write(fd_, data, size);
    if (n > 0) {
      data += n;
      size -= std::size_t(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p{fd_, POLLOUT, 0};
    ::poll(&p, 1, int(left.count()));
  }
  return true;
}

void SerialPort::close() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace osteon::devices
