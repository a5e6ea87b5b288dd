#include "osteon/devices/igtl_device.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <netdb.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <thread>
#include <unistd.h>

#include "osteon/core/error.h"
#include "osteon/core/handoff.h"
#include "osteon/devices/igtl_reader.h"

namespace osteon::devices {

namespace {

struct Received {
  std::uint64_t count = 0;  // transforms taken so far: a new one is a new sample
  glm::dvec3 positionMm{0.0};
  glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
};

int connectTo(const std::string& text, const std::string& host, const std::string& port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (::getaddrinfo(host.c_str(), port.c_str(), &hints, &found) != 0 || !found) {
    throw InputError(text + ": unknown host '" + host + "'");
  }
  int fd = -1;
  std::string reason = "no address";
  for (addrinfo* a = found; a; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (fd >= 0 && ::connect(fd, a->ai_addr, a->ai_addrlen) == 0) break;
    reason = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
  ::freeaddrinfo(found);
  if (fd < 0) throw InputError(text + ": cannot connect to " + host + ":" + port + ": " + reason);
  timeval timeout{0, 100000};  // the reader thread looks at `stop` this often
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  return fd;
}

class IgtlDevice final : public Device {
 public:
  IgtlDevice(const std::string& text, int fd, std::string name)
      : Device(text), fd_(fd), name_(std::move(name)) {
    reader_ = std::thread([this] { readLoop(); });
  }
  ~IgtlDevice() override {
    stop_.store(true);
    reader_.join();
    ::close(fd_);
  }

  Capabilities capabilities() const override {
    Capabilities c;
    c.pose = true;
    c.worldFrame = true;
    return c;
  }

  void poll(double nowS, DeviceSample& sample) noexcept override {
    const Received& r = latest_.read();
    sample.connected = open_.load(std::memory_order_acquire) && r.count > 0;
    if (r.count == 0) return;
    if (r.count != seen_) {
      seen_ = r.count;
      seenS_ = nowS;
      sample.positionMm = r.positionMm;
      sample.orientation = r.orientation;
    }
    // Trackers send at 20-60 Hz: the pose holds between messages (fresh at each poll) until the
    // stream has been silent for kStoppedS; then the sample ages and the safety layer faults it.
    if (nowS - seenS_ < kStoppedS) sample.tS = nowS;
    sample.drillOn = sample.connected;
  }

 private:
  void readLoop() {
    IgtlStreamReader reader({"TRANSFORM", "TDATA", "QTDATA"}, std::size_t(1) << 20);
    std::uint8_t buffer[4096];
    IgtlMessage m;
    Received r;
    while (!stop_.load()) {
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) break;
      if (n < 0) continue;
      if (!reader.feed(buffer, static_cast<std::size_t>(n))) break;
      while (reader.next(m)) {
        glm::dmat4 t;
        if (!decodeIgtlPose(m, name_, t)) continue;
        // RAS -> LPS on both sides: F t F with F = diag(-1, -1, 1).
        const glm::dmat3 f(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
        const glm::dmat3 rotation = f * glm::dmat3(t) * f;
        r.orientation = glm::normalize(glm::quat_cast(rotation));
        r.positionMm = f * glm::dvec3(t[3]);
        ++r.count;
        latest_.write(r);
      }
    }
    open_.store(false, std::memory_order_release);
  }

  int fd_;
  std::string name_;
  std::thread reader_;
  std::atomic<bool> stop_{false}, open_{true};
  core::TripleBuffer<Received> latest_;
  static constexpr double kStoppedS = 0.25;
  std::uint64_t seen_ = 0;  // poll's thread only
  double seenS_ = 0.0;
};

}  // namespace

std::unique_ptr<Device> openIgtlDevice(const std::string& text, const std::string& argument) {
  const std::size_t slash = argument.find('/');
  const std::string address = argument.substr(0, slash);
  const std::string name = slash == std::string::npos ? "" : argument.substr(slash + 1);
  const std::size_t colon = address.rfind(':');
  const std::string host = colon == std::string::npos ? "" : address.substr(0, colon);
  const std::string port = colon == std::string::npos ? "" : address.substr(colon + 1);
  const bool digits = !port.empty() && port.size() <= 5 &&
                      port.find_first_not_of("0123456789") == std::string::npos;
  if (host.empty() || !digits || std::stoi(port) < 1 || std::stoi(port) > 65535 ||
      (slash != std::string::npos && name.empty())) {
    throw InputError(text +
                     ": expected igtl:HOST:PORT[/NAME], e.g. igtl:127.0.0.1:18944/DrillToRAS");
  }
  return std::make_unique<IgtlDevice>(text, connectTo(text, host, port), name);
}

}  // namespace osteon::devices
