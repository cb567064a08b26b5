// The local pages' guard (agents/human/page_guard.h) on a real HTTP server over loopback: what a
// page of another site, a DNS name rebound to 127.0.0.1 or a stranger on the network can and
// cannot make it do. The play page, the viewer and the audit install exactly this guard; the
// Chromium tests (bus/view_test.cc) drive them through it.

#include "agents/human/page_guard.h"

// Before httplib.h: it brings in <resolv.h>, whose `_res` macro breaks Eigen's headers.
#include "tests/support/fixture_dataset.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <sys/stat.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <thread>

namespace mtg {
namespace {

using nlohmann::json;

// A page with one state-changing route, one that throws, and a counter of moves it made.
class GuardedPage {
 public:
  GuardedPage(const std::string& host, const std::string& token) : guard_("the test page") {
    guard_.install(server_);
    server_.Get("/api/state", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(R"({"ok":true})", "application/json");
    });
    server_.Post("/api/move", [this](const httplib::Request&, httplib::Response& res) {
      ++moves_;
      res.set_content(R"({"moved":true})", "application/json");
    });
    server_.Get("/api/broken", [](const httplib::Request&, httplib::Response&) {
      throw std::runtime_error("stoll");
    });
    port_ = server_.bind_to_any_port(host);
    guard_.set_address({host, port_, token});
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~GuardedPage() {
    server_.stop();
    thread_.join();
  }
  int port() const { return port_; }
  int moves() const { return moves_; }

 private:
  httplib::Server server_;
  web::PageGuard guard_;
  int port_ = 0;
  std::atomic<int> moves_{0};
  std::thread thread_;
};

struct Answer {
  int status = 0;
  json body;
  std::string cookie;
};

Answer request(int port, const std::string& method, const std::string& path, const httplib::Headers& headers,
               const std::string& body = "", const std::string& type = "application/json") {
  httplib::Client c("127.0.0.1", port);
  const auto r = method == "GET" ? c.Get(path, headers) : c.Post(path, headers, body, type);
  if (!r) return {};
  return {r->status, json::parse(r->body, nullptr, false), r->get_header_value("Set-Cookie")};
}

TEST(PageGuardTest, ALoopbackPageAnswersOnlyItsOwnHostAndTakesOrdersOnlyFromItsOwnPage) {
  GuardedPage page("127.0.0.1", "");
  const std::string self = "127.0.0.1:" + std::to_string(page.port());
  EXPECT_EQ(request(page.port(), "GET", "/api/state", {{"Host", self}}).status, 200);
  EXPECT_EQ(request(page.port(), "GET", "/api/state", {{"Host", "localhost:" + std::to_string(page.port())}}).status, 200);

  // DNS rebinding: the browser sends the attacker's name as Host.
  const Answer rebound = request(page.port(), "GET", "/api/state", {{"Host", "evil.example:" + std::to_string(page.port())}});
  EXPECT_EQ(rebound.status, 403);
  EXPECT_NE(rebound.body["error"].get<std::string>().find("not for 'evil.example"), std::string::npos);

  // A page of another site: a "simple" cross-site POST (text/plain, no preflight) and a JSON one.
  const Answer simple = request(page.port(), "POST", "/api/move", {{"Host", self}, {"Origin", "http://evil.example"}},
                                R"({"key":"o1"})", "text/plain");
  EXPECT_EQ(simple.status, 403);
  EXPECT_EQ(request(page.port(), "POST", "/api/move", {{"Host", self}, {"Origin", "http://evil.example"}}, "{}").status, 403);
  // Its own page, but not JSON: refused too (a form on another site could send that without Origin).
  EXPECT_EQ(request(page.port(), "POST", "/api/move", {{"Host", self}}, "key=o1", "application/x-www-form-urlencoded").status, 415);
  EXPECT_EQ(page.moves(), 0) << "no refused request reached the route";
  EXPECT_EQ(request(page.port(), "POST", "/api/move", {{"Host", self}, {"Origin", "http://" + self}}, "{}").status, 200);
  EXPECT_EQ(page.moves(), 1);

  // Every error is one line of JSON, also where no route wrote a body.
  const Answer missing = request(page.port(), "GET", "/api/nope", {{"Host", self}});
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(missing.body["error"], "no such page or API route: GET /api/nope");
  const Answer broken = request(page.port(), "GET", "/api/broken", {{"Host", self}});
  EXPECT_EQ(broken.status, 500);
  EXPECT_EQ(broken.body["error"], "the test page failed on GET /api/broken: stoll");
}

TEST(PageGuardTest, APageBeyondLoopbackNeedsTheTokenOnceThenItsCookie) {
  EXPECT_THROW(GuardedPage("0.0.0.0", ""), std::exception) << "no page listens beyond loopback without a token";
  const std::string token = web::random_token();
  ASSERT_EQ(token.size(), 64u);
  EXPECT_NE(token, web::random_token());
  GuardedPage page("0.0.0.0", token);
  const std::string host = "192.0.2.7:" + std::to_string(page.port());  // any name: the page listens on all
  EXPECT_EQ(request(page.port(), "GET", "/api/state", {{"Host", host}}).status, 403);
  EXPECT_EQ(request(page.port(), "GET", "/api/state?token=" + std::string(64, '0'), {{"Host", host}}).status, 403);
  const Answer opened = request(page.port(), "GET", "/?token=" + token, {{"Host", host}});
  EXPECT_EQ(opened.status, 404) << "the guard let it through to the routes";
  const std::string cookie = "mtg_page_" + std::to_string(page.port()) + "=" + token;
  EXPECT_EQ(opened.cookie, cookie + "; Path=/; HttpOnly; SameSite=Strict");
  EXPECT_EQ(request(page.port(), "GET", "/api/state", {{"Host", host}, {"Cookie", "a=1; " + cookie}}).status, 200);
  EXPECT_EQ(request(page.port(), "GET", "/api/state", {{"Host", host}, {"Cookie", "mtg_page_1=" + token}}).status, 403)
      << "a cookie for another port is not this page's";
  EXPECT_EQ(request(page.port(), "POST", "/api/move", {{"Host", host}, {"Cookie", cookie}, {"Origin", "http://" + host}},
                    "{}").status,
            200);
  EXPECT_EQ(web::page_url({"127.0.0.1", 8780, ""}), "http://127.0.0.1:8780/");
  EXPECT_EQ(web::page_url({"::1", 8780, ""}), "http://[::1]:8780/");
  EXPECT_NE(web::page_url({"10.1.2.3", 8780, token}).find("http://10.1.2.3:8780/?token=" + token), std::string::npos);
}

TEST(PageGuardTest, TheTokenFileIsTheOwnersAlone) {
  testing::FixtureDataset fx;
  const std::string file = (fx.root() / "play.token").string();
  const std::string token = web::random_token();
  web::write_token_file(file, token);
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600);
  EXPECT_EQ(web::read_token_file(file), token);
  web::write_token_file(file, "short");
  EXPECT_THROW(web::read_token_file(file), std::exception);
}

}  // namespace
}  // namespace mtg
