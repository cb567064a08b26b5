#pragma once
// The play page's HTTP side: the page itself and the JSON API over a PlayDesk (docs/view.md,
// "Play"). Bound to 127.0.0.1 by default: whoever reaches the port plays the episode.

#include <memory>
#include <string>
#include <thread>

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

  /// Binds and serves on a thread of its own. @throws mtg::Error when the port is taken.
  void start(const std::string& host, int port);

 private:
  PlayDesk& desk_;
  std::unique_ptr<httplib::Server> http_;
  std::thread thread_;
};

}  // namespace mtg::agents
