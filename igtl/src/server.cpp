// The producer side of the server: on the visual thread, what changed into the queues.
#include <algorithm>
#include <sstream>
#include <unistd.h>

#include "osteon/core/option_error.h"
#include "server_impl.h"

namespace osteon::igtl {

namespace {

namespace geo = osteon::geometry;

// The voxel box of the listed bricks, clipped to the grid.
void brickBox(const geo::VoxelGrid& grid, const std::vector<std::size_t>& bricks, glm::ivec3& lo,
              glm::ivec3& hi) {
  lo = grid.dims();
  hi = glm::ivec3(0);
  for (const std::size_t b : bricks) {
    const glm::ivec3 first = grid.brickCoord(b) * geo::VoxelGrid::kBrickSize;
    lo = glm::min(lo, first);
    hi = glm::max(hi, glm::min(first + geo::VoxelGrid::kBrickSize, grid.dims()));
  }
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

ImageContent parseImageContent(const std::string& text) {
  if (text == "fill") return ImageContent::Fill;
  if (text == "density") return ImageContent::Density;
  throw OptionError("igtl.content", text, "fill or density");
}

Server::Server(const ServerOptions& options, const simulation::Tool& tool)
    : impl_(std::make_unique<Impl>()) {
  if (options.port < 0 || options.port > 65535) {
    throw OptionError("igtl.port", std::to_string(options.port), "a TCP port, 0 to 65535");
  }
  impl_->options = options;
  toolModel(tool, impl_->toolPointsMm, impl_->toolTriangles);
  impl_->startNetwork();
}

Server::~Server() {
  stop(0.0);
}

int Server::port() const {
  return impl_->boundPort;
}

void Server::publish(simulation::LiveRuntime& live, bool last) noexcept {
  Impl& m = *impl_;
  try {
    const double t = nowS();
    const geo::VoxelGrid& grid = live.visualGrid();
    if (grid.dims() != m.gridDims) {
      m.gridDims = grid.dims();
      m.brickPending.assign(grid.brickCount(), 0);
      m.pendingBricks.clear();
      std::lock_guard<std::mutex> lock(m.mutex);
      for (const auto& c : m.clients) c->needsVolume = true;
    }
    for (const std::size_t b : live.changedBricks()) {
      if (!m.brickPending[b]) m.pendingBricks.push_back(b);
      m.brickPending[b] = 1;
    }
    const simulation::DisplayState& d = live.display();
    SharedBytes transform, strings[2], image, volume, tool, surface;
    if (d.tS >= 0.0 && (last || t - m.lastTransformS >= 1.0 / m.options.transformHz)) {
      transform = packTransform("DrillToRAS", toolToRas(d.pose));
      m.lastTransformS = t;
    }
    if (d.tS >= 0.0 && (last || t - m.lastStringS >= 0.1)) {
      strings[0] = packString("Force", number(glm::length(d.contact.forceN)));
      strings[1] = packString("RemovedVolume", number(d.removedVolumeMm3));
      m.lastStringS = t;
    }
    if (!m.pendingBricks.empty() && (last || t - m.lastImageS >= 1.0 / m.options.imageHz)) {
      glm::ivec3 lo, hi;
      brickBox(grid, m.pendingBricks, lo, hi);
      image = packImage("Bone", grid, m.options.content, lo, hi);
      for (const std::size_t b : m.pendingBricks) m.brickPending[b] = 0;
      m.pendingBricks.clear();
      m.lastImageS = t;
    }
    const bool surfaceDue =
        m.options.surfaceEveryS > 0.0 && t - m.lastSurfaceS >= m.options.surfaceEveryS;
    bool needVolume = false, needTool = false, wantSurface = surfaceDue;
    {
      std::lock_guard<std::mutex> lock(m.mutex);
      for (const auto& c : m.clients) {
        needVolume = needVolume || c->needsVolume;
        needTool = needTool || c->needsTool;
        wantSurface = wantSurface || c->wantsSurface;
      }
    }
    // Packed outside the lock: the network thread goes on writing meanwhile.
    if (needVolume) volume = packImage("Bone", grid, m.options.content, glm::ivec3(0), grid.dims());
    if (needTool) tool = packPolyData("DrillModel", m.toolPointsMm, m.toolTriangles, true);
    if (wantSurface) {
      const geo::TriangleMesh mesh = live.visualSurface().mesh().toTriangleMesh();
      surface = packPolyData("BoneSurface", mesh.positionsMm, mesh.triangles, true);
      m.lastSurfaceS = t;
    }
    std::lock_guard<std::mutex> lock(m.mutex);
    m.stats.transforms += transform ? 1u : 0u;
    m.stats.strings += strings[0] ? 2u : 0u;
    m.stats.images += image ? 1u : 0u;
    m.stats.surfaces += surface ? 1u : 0u;
    for (const auto& cp : m.clients) {
      Client& c = *cp;
      if (c.needsTool && tool) {
        m.pushLocked(c, tool, false);
        c.needsTool = false;
      }
      if (c.needsVolume && volume) {
        c.needsVolume = false;  // set again if this one is dropped
        ++m.stats.volumesSent;
        m.pushLocked(c, volume, true);
      } else if (image) {
        m.pushLocked(c, image, true);
      }
      if (transform) m.pushLocked(c, transform, false);
      for (const SharedBytes& s : strings) {
        if (s) m.pushLocked(c, s, false);
      }
      if (surface && (surfaceDue || c.wantsSurface)) {
        m.pushLocked(c, surface, false);
        c.wantsSurface = false;
      }
    }
    m.wake();
  } catch (...) {
    // Out of memory packing a volume: this round is lost, the next one tries again.
  }
}

void Server::sendString(const std::string& name, const std::string& text) noexcept {
  Impl& m = *impl_;
  try {
    const SharedBytes bytes = packString(name, text);
    std::lock_guard<std::mutex> lock(m.mutex);
    auto kept = std::find_if(m.keptStrings.begin(), m.keptStrings.end(),
                             [&](const auto& k) { return k.first == name; });
    if (kept == m.keptStrings.end()) {
      m.keptStrings.emplace_back(name, bytes);
    } else {
      kept->second = bytes;
    }
    ++m.stats.strings;
    for (const auto& c : m.clients) m.pushLocked(*c, bytes, false);
    m.wake();
  } catch (...) {
    // Out of memory: the string is lost, the session goes on.
  }
}

ServerStats Server::stop(double flushS) {
  Impl& m = *impl_;
  if (m.network.joinable()) {
    m.flushUntilS.store(nowS() + flushS);
    m.stopping.store(true, std::memory_order_release);
    m.wake();
    m.network.join();
    for (int& fd : m.wakeFds) {
      if (fd >= 0) ::close(fd);
      fd = -1;
    }
  }
  return stats();
}

ServerStats Server::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace osteon::igtl
