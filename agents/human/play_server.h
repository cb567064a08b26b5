#pragma once
// The play page's HTTP side: the page itself and the JSON API over a PlayDesk (docs/view.md,
// "Play"). Bound to 127.0.0.1 by default; only the page itself drives it (page_guard.h), and
// beyond loopback only a browser that opened the URL with the run's token.

#include <memory>
#include <string>
#include <thread>

#include "agents/human/page_guard.h"
#include "agents/human/play_desk.h"

namespace httplib {
class Server;
}

namespace mtg::agents {

class PlayServer {
 public:
  explicit PlayServer(PlayDesk& desk);
  ~PlayServer();  // stops serving
  PlayServer(const PlayServer&) = delete;
  PlayServer& operator=(const PlayServer&) = delete;

  /// Binds and serves on a thread of its own; `token` is required (and checked) when `host` is
  /// not a loopback address. @throws mtg::Error when the port is taken or a token is missing.
  void start(const std::string& host, int port, const std::string& token = "");
  /// The same on the Unix socket `path` (owner only): the page's address, host:port with its
  /// token, is relayed to it from outside a run's namespace (orchestrator/run/page_relay.h).
  void start_unix(const std::string& path, const std::string& host, int port, const std::string& token = "");

 private:
  PlayDesk& desk_;
  std::unique_ptr<httplib::Server> http_;
  web::PageGuard guard_;
  std::thread thread_;
};

}  // namespace mtg::agents
