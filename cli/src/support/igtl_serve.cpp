#include "support/igtl_serve.h"

#include <iostream>

#include "osteon/core/error.h"
#include "osteon/core/option_error.h"
#include "osteon/igtl/server.h"

namespace osteon::cli {

namespace sim = osteon::simulation;

void checkIgtlOptions(const IgtlCommandOptions& options, bool live) {
  if (!options.port) {
    if (options.bind != "127.0.0.1") throw InputError("--igtl-bind: only with --igtl PORT");
    if (options.content != "fill") throw InputError("--igtl-content: only with --igtl PORT");
    if (options.surfaceEveryS) throw InputError("--igtl-surface-every: only with --igtl PORT");
    return;
  }
  if (!live) {
    throw InputError("--igtl: only for a live run (--threaded, or a live device)");
  }
  if (*options.port < 1 || *options.port > 65535) {
    throw InputError("--igtl " + std::to_string(*options.port) + ": a TCP port, 1 to 65535");
  }
  igtl::parseImageContent(options.content);
  if (options.surfaceEveryS && !(*options.surfaceEveryS > 0.0)) {
    throw InputError("--igtl-surface-every " + std::to_string(*options.surfaceEveryS) +
                     ": seconds, above 0");
  }
}

struct IgtlServe::Impl {
  std::unique_ptr<igtl::Server> server;
  std::string where;
};

IgtlServe::IgtlServe(const IgtlCommandOptions& options, const sim::Session& session)
    : impl_(std::make_unique<Impl>()) {
  if (!options.port) return;
  igtl::ServerOptions so;
  so.port = *options.port;
  so.bindAddress = options.bind;
  so.content = igtl::parseImageContent(options.content);
  if (options.surfaceEveryS) so.surfaceEveryS = *options.surfaceEveryS;
  impl_->server = std::make_unique<igtl::Server>(so, session.simulation().tool());
  impl_->where = options.bind + ":" + std::to_string(impl_->server->port());
  std::cerr << "osteon: serving OpenIGTLink on " << impl_->where << "\n";
}

IgtlServe::~IgtlServe() = default;

void IgtlServe::attach(sim::RuntimeOptions& runtime) {
  igtl::Server* server = impl_->server.get();
  if (!server) return;
  runtime.onVisual = [server](sim::LiveRuntime& live, bool last) { server->publish(live, last); };
}

nlohmann::json IgtlServe::finish() {
  if (!impl_->server) return nullptr;
  const igtl::ServerStats s = impl_->server->stop();
  return {{"address", impl_->where},    {"clients", s.clients},  {"messages_sent", s.messagesSent},
          {"bytes_sent", s.bytesSent},  {"dropped", s.dropped},  {"volumes_sent", s.volumesSent},
          {"transforms", s.transforms}, {"images", s.images},    {"surfaces", s.surfaces},
          {"strings", s.strings},       {"rejected", s.rejected}};
}

}  // namespace osteon::cli
