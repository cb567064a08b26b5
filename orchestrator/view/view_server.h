#pragma once
// `mtg view`: the local web viewer over run folders. An HTTP server (cpp-httplib) bound to
// 127.0.0.1 by default, serving one static page compiled into the binary (no network fetch) and the
// JSON API the page reads (docs/view.md).

#include <memory>
#include <string>
#include <vector>

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

  /// Binds `host`:`port` (0 = any free port) and returns the port.
  /// @throws mtg::Error when the address cannot be bound (e.g. the port is taken).
  int bind(const std::string& host, int port);
  /// Serves until stop() (from another thread or a signal handler's thread).
  void serve();
  void stop();

 private:
  void add_routes();
  RunView* run(const std::string& name);

  std::vector<std::unique_ptr<RunView>> runs_;
  std::unique_ptr<httplib::Server> http_;
};

}  // namespace mtg::orchestrator::view
