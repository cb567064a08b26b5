#pragma once
// HTTP for model adapters that live in a network namespace of their own. An isolated run's
// processes share a bus nothing outside the run can reach (docs/runtime.md, "Isolation"), and so
// they reach no network either; `mtg run` keeps its outer process outside the namespace, and that
// process makes the adapters' calls for them: one Unix-socket connection per call (a socket file
// reaches across network namespaces), the request in, the response out, curl outside with the
// machine's own DNS, proxies and loopback (a model server on localhost stays reachable).
//
// Frames: a 4-byte big-endian length, then the bytes. Request: a JSON header (url, headers,
// timeouts) and the raw body. Response: a JSON header (status, headers, transport_error,
// elapsed_ms) and the raw body.

#include <atomic>
#include <memory>
#include <string>

#include "agents/vlm/http_client.h"

namespace mtg::vlm {

/// The environment variable that names the relay socket for http_post().
inline constexpr const char* kHttpRelayEnv = "MTG_HTTP_RELAY";

class HttpRelayServer {
 public:
  /// Listens on a socket in a new private folder (0700) under $TMPDIR or /tmp.
  /// @throws mtg::Error when the socket cannot be made.
  HttpRelayServer();
  /// Stops accepting and removes the socket and its folder.
  ~HttpRelayServer();
  HttpRelayServer(const HttpRelayServer&) = delete;
  HttpRelayServer& operator=(const HttpRelayServer&) = delete;

  const std::string& socket_path() const { return socket_path_; }
  /// Serves calls on threads of its own until destroyed.
  void start();

 private:
  struct State;
  std::string dir_;
  std::string socket_path_;
  std::shared_ptr<State> state_;
};

/// One call through the relay at `socket_path`; network trouble, a dead relay included, is in
/// transport_error, as with http_post.
HttpResponse relay_post(const std::string& socket_path, const HttpRequest& request, const std::atomic<bool>* cancel);

}  // namespace mtg::vlm
