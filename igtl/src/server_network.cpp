// The server's network thread: accepts clients, writes their queues without blocking, reads
// their requests through the devices::IgtlStreamReader. POSIX sockets, non-blocking, one poll() per
// round.
#include <arpa/inet.h>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "osteon/core/option_error.h"
#include "server_impl.h"

namespace osteon::igtl {

namespace {

void setNonBlocking(int fd) {
  const int flags = fcntl(fd, F_GETFL, 0);
  fcntl(fd, F_SETFL, flags | O_NONBLOCK);
}

// Writes what the client's socket takes now; false when the connection is gone.
bool writeSome(Client& c, ServerStats& stats) {
  while (!c.queue.empty()) {
    const Bytes& front = *c.queue.front();
    const ssize_t n = ::send(c.fd, front.data() + c.frontSent, front.size() - c.frontSent,
                             MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
    c.frontSent += static_cast<std::size_t>(n);
    stats.bytesSent += static_cast<std::uint64_t>(n);
    if (c.frontSent < front.size()) return true;
    c.queue.pop_front();
    c.frontSent = 0;
    ++stats.messagesSent;
  }
  return true;
}

// Reads the client's requests; false when the connection is gone or its stream is broken.
bool readSome(Client& c, ServerStats& stats) {
  std::uint8_t buffer[4096];
  for (;;) {
    const ssize_t n = ::recv(c.fd, buffer, sizeof buffer, MSG_DONTWAIT);
    if (n == 0) return false;
    if (n < 0) break;
    if (!c.reader.feed(buffer, static_cast<std::size_t>(n))) break;
  }
  devices::IgtlMessage m;
  while (c.reader.next(m)) {
    if (m.type == "GET_POLYDATA") c.wantsSurface = true;
    if (m.type == "GET_IMAGE") c.needsVolume = true;
  }
  if (c.reader.broken()) {
    ++stats.rejected;
    return false;
  }
  return true;
}

}  // namespace

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void Server::Impl::startNetwork() {
  listenFd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (listenFd < 0)
    throw OptionError("igtl.port", std::to_string(options.port), std::strerror(errno));
  const int one = 1;
  ::setsockopt(listenFd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(options.port));
  if (::inet_pton(AF_INET, options.bindAddress.c_str(), &addr.sin_addr) != 1) {
    ::close(listenFd);
    throw OptionError("igtl.bind", options.bindAddress, "not an IPv4 address");
  }
  if (::bind(listenFd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(listenFd, 16) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(listenFd);
    throw OptionError("igtl.port", std::to_string(options.port),
                      "cannot listen on " + options.bindAddress + ": " + reason);
  }
  socklen_t len = sizeof addr;
  ::getsockname(listenFd, reinterpret_cast<sockaddr*>(&addr), &len);
  boundPort = ntohs(addr.sin_port);
  setNonBlocking(listenFd);
  if (::pipe(wakeFds) != 0) throw std::runtime_error("igtl: no pipe");
  setNonBlocking(wakeFds[0]);
  setNonBlocking(wakeFds[1]);
  network = std::thread([this] { networkLoop(); });
}

void Server::Impl::wake() {
  const char byte = 1;
  [[maybe_unused]] const ssize_t n = ::write(wakeFds[1], &byte, 1);
}

void Server::Impl::pushLocked(Client& c, const SharedBytes& bytes, bool image) {
  if (c.queue.size() >= options.queueMessages) {
    ++stats.dropped;
    if (image) c.needsVolume = true;  // its volume missed an update: the whole one again
    return;
  }
  c.queue.push_back(bytes);
}

void Server::Impl::networkLoop() {
  std::vector<pollfd> fds;
  for (;;) {
    fds.clear();
    fds.push_back({wakeFds[0], POLLIN, 0});
    fds.push_back({listenFd, POLLIN, 0});
    bool anyQueued = false;
    {
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& c : clients) {
        const auto events = static_cast<short>(POLLIN | (c->queue.empty() ? 0 : POLLOUT));
        anyQueued = anyQueued || !c->queue.empty();
        fds.push_back({c->fd, events, 0});
      }
    }
    if (stopping.load(std::memory_order_acquire) && (!anyQueued || nowS() > flushUntilS.load()))
      break;
    ::poll(fds.data(), fds.size(), 20);
    char drain[64];
    while (::read(wakeFds[0], drain, sizeof drain) > 0) {
    }
    for (;;) {
      const int fd = ::accept(listenFd, nullptr, nullptr);
      if (fd < 0) break;
      setNonBlocking(fd);
      const int one = 1;
      ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      if (options.sendBufferBytes > 0) {
        ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &options.sendBufferBytes,
                     sizeof options.sendBufferBytes);
      }
      auto c = std::make_unique<Client>();
      c->fd = fd;
      std::lock_guard<std::mutex> lock(mutex);
      for (const auto& kept : keptStrings) pushLocked(*c, kept.second, false);
      clients.push_back(std::move(c));
      ++stats.clients;
    }
    std::lock_guard<std::mutex> lock(mutex);
    for (auto it = clients.begin(); it != clients.end();) {
      Client& c = **it;
      if (!readSome(c, stats) || !writeSome(c, stats)) {
        ::close(c.fd);
        it = clients.erase(it);
      } else {
        ++it;
      }
    }
  }
  closeAll();
}

void Server::Impl::closeAll() {
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& c : clients) {
    stats.dropped += c->queue.size();
    ::close(c->fd);
  }
  clients.clear();
  if (listenFd >= 0) ::close(listenFd);
  listenFd = -1;
}

}  // namespace osteon::igtl
