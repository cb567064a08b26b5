#pragma once
// Who may drive a local page (the play page, `mtg view`, `mtg audit`). A page of another web
// site open in the user's browser can send requests to 127.0.0.1, and a DNS name rebound to
// 127.0.0.1 can read the answers; neither should play a move, answer an audit or read a run.
// The guard, run before every route (docs/view.md, "Who may drive a page"):
//   - the request's Host must be an address the page serves (127.0.0.1, localhost, [::1] or the
//     address given with --host, with the port), unless the page listens on every address;
//   - a request that changes state (any method but GET and HEAD) must carry application/json and
//     no Origin but the page's own (a browser cannot send a cross-site JSON request without
//     asking first, and asking is refused here: there is no OPTIONS route);
//   - a page listening beyond loopback also needs the random token printed when it starts: in the
//     URL the user opens (?token=...), kept afterwards in a cookie of this port only.
// Every refusal, and every error without a body (an unknown route, a handler that threw), is
// answered with one line of JSON, {"error": "..."}.

#include <memory>
#include <string>

namespace httplib {
class Server;
}

namespace mtg::web {

/// True for the addresses that only this machine reaches (127.0.0.0/8, ::1, "localhost").
bool is_loopback(const std::string& host);

/// 32 random bytes from OpenSSL as 64 hex digits. @throws mtg::Error when OpenSSL cannot draw.
std::string random_token();

/// Reads a token written by write_token_file. @throws mtg::Error naming the file.
std::string read_token_file(const std::string& file);

/// Writes `token` to `file`, readable by its owner only (mode 600 from its creation).
void write_token_file(const std::string& file, const std::string& token);

/// The address a page serves, told to its guard once bound.
struct PageAddress {
  std::string host;   // as given to bind ("127.0.0.1", "0.0.0.0", "::", a name or an address)
  int port = 0;
  std::string token;  // "" = none needed (loopback pages); required when host is not loopback
};

/// The URL a user opens: http://HOST:PORT/, with ?token=... when one is needed. A page bound to
/// every address names this machine's host name.
std::string page_url(const PageAddress& address);

/// Installs the checks above on `server` (its pre-routing, error and exception handlers). The
/// address is read at each request, so it may be set after binding. `what` names the page in
/// refusals ("the play page").
class PageGuard {
 public:
  explicit PageGuard(std::string what);
  void install(httplib::Server& server);
  /// @throws mtg::Error when `address` listens beyond loopback without a token.
  void set_address(PageAddress address);
  const PageAddress& address() const { return address_; }

 private:
  std::string what_;
  PageAddress address_;
};

}  // namespace mtg::web
