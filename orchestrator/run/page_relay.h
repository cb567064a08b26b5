#pragma once
// The play page of a run in its own network namespace (run_namespace.h): the human agent serves
// it on a Unix socket (filesystem sockets are not bound to a network namespace), and the outer
// `mtg play`, on the host's network, listens on the page's TCP address and relays each
// connection to that socket byte for byte. The browser sees the page where it always was; the
// run's bus stays in the namespace.

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace mtg::orchestrator {

/// Set in the inner run's environment: the Unix socket the human agent serves the page on.
inline constexpr const char* kPlaySocketEnv = "MTG_PLAY_SOCKET";

class PageRelay {
 public:
  /// Listens on `host`:`port` now (so a taken port fails before the run starts) and picks a
  /// socket path for the page. @throws mtg::Error naming the address when it cannot listen.
  PageRelay(const std::string& host, int port);
  ~PageRelay();  // stops relaying, closes the connections, removes the socket file
  PageRelay(const PageRelay&) = delete;
  PageRelay& operator=(const PageRelay&) = delete;

  const std::string& socket_path() const { return socket_path_; }
  /// Relays on threads of its own until destroyed.
  void start();

 private:
  void accept_loop();
  void relay(int client);

  std::string socket_path_;
  int listen_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread acceptor_;
  struct Connection {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> done;
  };
  std::mutex mutex_;
  std::vector<Connection> connections_;  // finished ones are joined as new ones come
  std::vector<int> open_fds_;  // shut down when stopping, so their threads end
};

}  // namespace mtg::orchestrator
