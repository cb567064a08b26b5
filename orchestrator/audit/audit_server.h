#pragma once
// The audit's local page and its JSON API (docs/view.md, "mtg audit"). It serves only what the
// agent would see and the person's answers; the truth stays in the store. Bound to 127.0.0.1 by
// default; only its own page drives it (agents/human/page_guard.h): a page of another site cannot
// answer for the person.

#include <filesystem>
#include <memory>
#include <mutex>
#include <string>

#include "agents/human/page_guard.h"
#include "orchestrator/audit/audit_store.h"

namespace httplib {
class Server;
}

namespace mtg::orchestrator::audit {

class AuditServer {
 public:
  /// Serves the audit in `dir` to one rater: the page shows and stores that rater's answers.
  AuditServer(const std::filesystem::path& dir, std::string rater = kDefaultRater);
  ~AuditServer();
  AuditServer(const AuditServer&) = delete;
  AuditServer& operator=(const AuditServer&) = delete;

  /// Binds `host`:`port` (0: any free port) and serves until stop(). @throws mtg::Error when the
  /// port is taken. Returns the port bound.
  int bind(const std::string& host, int port);
  /// The URL to open (with the token where one is needed); valid after bind().
  std::string url() const { return web::page_url(guard_.address()); }
  void serve();  // blocks
  void stop();

 private:
  void add_routes();

  std::mutex mutex_;  // the store is used by one request at a time
  AuditStore store_;
  std::string rater_;
  std::unique_ptr<httplib::Server> http_;
  web::PageGuard guard_{"the audit page"};
};

}  // namespace mtg::orchestrator::audit
