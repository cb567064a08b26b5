#pragma once
// One HTTPS POST through libcurl. Connections are kept per thread (a thread answers many calls to
// the same API), so only the first call of a thread pays for the TCP and TLS handshakes.

#include <atomic>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace mtg::vlm {

struct HttpRequest {
  std::string url;
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;
  double timeout_s = 120.0;          // the whole exchange; a stalled server fails the call
  double connect_timeout_s = 10.0;
};

struct HttpResponse {
  long status = 0;                              // 0 when no response arrived
  std::map<std::string, std::string> headers;   // names lower-cased; the last value wins
  std::string body;
  std::string transport_error;                  // curl's message when the exchange failed
  double elapsed_ms = 0.0;                      // telemetry only
};

/// Never throws for network trouble: it is reported in transport_error. `cancel`, when given and
/// set (by another thread), aborts the exchange. Inside an isolated run ($MTG_HTTP_RELAY set)
/// the call goes through the run's HTTP relay (http_relay.h), otherwise straight out.
HttpResponse http_post(const HttpRequest& request, const std::atomic<bool>* cancel = nullptr);

/// The call straight out through libcurl, whatever the environment says.
HttpResponse http_post_direct(const HttpRequest& request, const std::atomic<bool>* cancel = nullptr);

}  // namespace mtg::vlm
