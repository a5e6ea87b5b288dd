// The session served over OpenIGTLink (docs/slicer.md), to any number of clients (3D Slicer's
// OpenIGTLinkIF, trackers' tools, tests):
//   TRANSFORM DrillToRAS   the tool frame -> RAS, at up to transformHz
//   POLYDATA  DrillModel   the tool, in its own frame, once to each client
//   IMAGE     Bone         the whole volume once to each client, then the sub-volume of the
//                          bricks that changed, at up to imageHz
//   POLYDATA  BoneSurface  the crack-free surface in RAS, on GET_POLYDATA or every surfaceEveryS
//   STRING    Force, RemovedVolume   the force sent (N) and the bone removed (mm3)
//   STRING    (any, by sendString)   e.g. the exercise's Score: kept, and sent to clients that
//                                    connect later
// publish() is called on the threaded runtime's visual thread (RuntimeOptions::onVisual), never
// in a 1 kHz loop; it packs messages and puts them in each client's bounded queue. A network
// thread of the server's own writes them without blocking: a client that reads slowly or not
// at all only fills its queue, and what does not fit is dropped and counted (a dropped image
// update sends that client the whole volume again, so its volume is never wrong for long).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "osteon/simulation/live.h"
#include "osteon/simulation/tool.h"

namespace osteon::igtl {

enum class ImageContent { Fill, Density };
// "fill" or "density"; OptionError naming igtl.content otherwise.
ImageContent parseImageContent(const std::string& text);

struct ServerOptions {
  int port = 18944;                       // 0: any free port (Server::port() tells which)
  std::string bindAddress = "127.0.0.1";  // only this machine unless told otherwise
  ImageContent content = ImageContent::Fill;
  double transformHz = 100.0;
  double imageHz = 10.0;
  double surfaceEveryS = 0.0;       // 0: the surface on GET_POLYDATA only
  std::size_t queueMessages = 256;  // per client
  int sendBufferBytes = 0;          // > 0: each client socket's SO_SNDBUF (tests make it small)
};

struct ServerStats {
  std::uint64_t clients = 0;  // connections accepted
  std::uint64_t messagesSent = 0, bytesSent = 0;
  std::uint64_t dropped = 0;      // messages a full client queue had no room for
  std::uint64_t volumesSent = 0;  // whole volumes (one per client, more after drops)
  std::uint64_t transforms = 0, images = 0, surfaces = 0, strings = 0;  // packed
  std::uint64_t rejected = 0;  // client connections closed for a broken stream
};

class Server {
 public:
  // Binds and listens; throws OptionError naming igtl.port or igtl.bind when it cannot.
  Server(const ServerOptions& options, const simulation::Tool& tool);
  ~Server();  // stops
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const;
  // On the visual thread: what changed since the last call, into the clients' queues. last:
  // the run is over: everything pending goes out now, whatever the rates.
  void publish(simulation::LiveRuntime& live, bool last) noexcept;
  // A STRING message to every client now, from any thread but a 1 kHz loop. The latest text
  // of each name is kept and sent to every client that connects later (a score stays visible).
  void sendString(const std::string& name, const std::string& text) noexcept;
  // Gives the queues up to flushS to drain, then closes every connection.
  ServerStats stop(double flushS = 2.0);
  ServerStats stats() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace osteon::igtl
