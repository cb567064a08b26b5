#pragma once
// Serving a local page until Ctrl-C (or SIGTERM): `mtg view` and `mtg audit`.

#include <chrono>
#include <thread>

#include "bus/process/stop_signals.h"

namespace mtg::cli {

/// Serves `server` (bound already) until a stop signal arrives; `Server` has serve() and stop().
template <class Server>
void serve_until_stopped(Server& server) {
  process::install_stop_signals();
  std::thread watcher([&server] {
    while (!process::stop_signal_received()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    server.stop();
  });
  server.serve();
  watcher.join();
}

}  // namespace mtg::cli
