#pragma once
// `mtg view`: the local web viewer over run folders. An HTTP server (cpp-httplib) bound to
// 127.0.0.1 by default, serving one static page compiled into the binary (no network fetch) and the
// JSON API the page reads (docs/view.md). Only its own page reads it (agents/human/page_guard.h).

#include <memory>
#include <string>
#include <vector>

#include "agents/human/page_guard.h"
#include "orchestrator/view/run_view.h"

namespace httplib {
class Server;
}

namespace mtg::orchestrator::view {

class ViewServer {
 public:
  /// The runs are named by their folders' names (made unique with "-2", "-3", ... if needed).
  /// @throws mtg::Error naming a folder that is not a run.
  explicit ViewServer(const std::vector<std::filesystem::path>& run_dirs);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  /// Binds `host`:`port` (0 = any free port) and returns the port. Beyond loopback a random
  /// token is drawn; url() carries it. @throws mtg::Error when the address cannot be bound.
  int bind(const std::string& host, int port);
  /// The URL to open (with the token where one is needed); valid after bind().
  std::string url() const { return web::page_url(guard_.address()); }
  /// Serves until stop() (from another thread or a signal handler's thread).
  void serve();
  void stop();

 private:
  void add_routes();
  RunView* run(const std::string& name);

  std::vector<std::unique_ptr<RunView>> runs_;
  std::unique_ptr<httplib::Server> http_;
  web::PageGuard guard_{"the viewer"};
};

}  // namespace mtg::orchestrator::view
