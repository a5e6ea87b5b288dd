// The server's state, shared by its producer side (server.cpp, the visual thread) and its
// network thread (server_network.cpp). One mutex guards the clients and their queues; it is
// held for pushes and non-blocking writes only, never by a 1 kHz loop.
#pragma once

#include <atomic>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "messages.h"
#include "osteon/devices/igtl_reader.h"
#include "osteon/igtl/server.h"

namespace osteon::igtl {

struct Client {
  int fd = -1;
  std::deque<SharedBytes> queue;
  std::size_t frontSent = 0;  // bytes of queue.front() already written
  bool needsVolume = true;    // the whole volume (new, or an image update was dropped)
  bool needsTool = true;
  bool wantsSurface = false;
  devices::IgtlStreamReader reader{{"GET_POLYDATA", "GET_IMAGE", "GET_TRANS"},
                                   std::size_t(1) << 16};
};

struct Server::Impl {
  ServerOptions options;
  std::vector<glm::dvec3> toolPointsMm;
  std::vector<glm::u32vec3> toolTriangles;
  int listenFd = -1;
  int wakeFds[2] = {-1, -1};  // a pipe: the producer wakes the network thread
  int boundPort = 0;
  std::thread network;
  std::atomic<bool> stopping{false};
  std::atomic<double> flushUntilS{0.0};

  mutable std::mutex mutex;  // guards clients and stats
  std::vector<std::unique_ptr<Client>> clients;
  ServerStats stats;
  std::vector<std::pair<std::string, SharedBytes>> keptStrings;  // by name, the latest text

  // Producer side (the visual thread only).
  std::vector<std::uint8_t> brickPending;  // per brick: changed since the last image
  std::vector<std::size_t> pendingBricks;
  glm::ivec3 gridDims{-1};  // a new grid (the viewer opened another file): the whole one again
  double lastTransformS = -1e9, lastImageS = -1e9, lastSurfaceS = -1e9, lastStringS = -1e9;

  void startNetwork();  // server_network.cpp
  void networkLoop();
  void closeAll();
  void wake();
  // Under the mutex: into one client's queue, or counted as dropped.
  void pushLocked(Client& c, const SharedBytes& bytes, bool image);
};

double nowS();

}  // namespace osteon::igtl
