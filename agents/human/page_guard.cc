#include "agents/human/page_guard.h"

#include <fcntl.h>
#include <httplib.h>
#include <openssl/crypto.h>
#include <openssl/rand.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "agents/human/json_reply.h"
#include "core/util/error.h"

namespace mtg::web {
namespace {

bool is_wildcard(const std::string& host) { return host.empty() || host == "0.0.0.0" || host == "::" || host == "[::]"; }

bool same_secret(const std::string& a, const std::string& b) {
  return a.size() == b.size() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

std::string cookie_name(int port) { return "mtg_page_" + std::to_string(port); }

// The value of cookie `name` in a Cookie header ("a=1; b=2"), or "".
std::string cookie_value(const std::string& header, const std::string& name) {
  std::size_t at = 0;
  while (at < header.size()) {
    std::size_t end = header.find(';', at);
    if (end == std::string::npos) end = header.size();
    std::string pair = header.substr(at, end - at);
    const std::size_t first = pair.find_first_not_of(' ');
    pair = first == std::string::npos ? "" : pair.substr(first);
    if (pair.rfind(name + "=", 0) == 0) return pair.substr(name.size() + 1);
    at = end + 1;
  }
  return "";
}

// Host names as a browser writes them in the Host header: IPv6 addresses in brackets.
std::string host_for_url(const std::string& host) {
  return host.find(':') != std::string::npos && host.front() != '[' ? "[" + host + "]" : host;
}

bool changes_state(const std::string& method) { return method != "GET" && method != "HEAD"; }

}  // namespace

bool is_loopback(const std::string& host) {
  return host == "localhost" || host == "::1" || host == "[::1]" || host.rfind("127.", 0) == 0;
}

std::string random_token() {
  std::array<unsigned char, 32> bytes{};
  if (RAND_bytes(bytes.data(), static_cast<int>(bytes.size())) != 1) {
    throw Error("cannot draw a page token: OpenSSL RAND_bytes failed");
  }
  std::string hex;
  for (const unsigned char b : bytes) {
    char digits[3];
    std::snprintf(digits, sizeof digits, "%02x", b);
    hex += digits;
  }
  return hex;
}

void write_token_file(const std::string& file, const std::string& token) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) throw Error("cannot write the page token " + file + ": " + std::strerror(errno));
  const bool written = ::fchmod(fd, 0600) == 0 &&
                       ::write(fd, token.data(), token.size()) == static_cast<ssize_t>(token.size());
  ::close(fd);
  if (!written) throw Error("cannot write the page token " + file);
}

std::string read_token_file(const std::string& file) {
  std::ifstream in(file);
  std::string token;
  if (!in || !std::getline(in, token) || token.size() < 32) {
    throw Error(file + ": no page token (at least 32 characters) in it");
  }
  return token;
}

std::string page_url(const PageAddress& address) {
  std::string host = address.host;
  if (is_wildcard(host)) {
    std::array<char, 256> name{};
    host = ::gethostname(name.data(), name.size() - 1) == 0 && name[0] != '\0' ? name.data() : "127.0.0.1";
  }
  std::string url = "http://" + host_for_url(host) + ":" + std::to_string(address.port) + "/";
  if (!address.token.empty()) url += "?token=" + address.token;
  return url;
}

PageGuard::PageGuard(std::string what) : what_(std::move(what)) {}

void PageGuard::set_address(PageAddress address) {
  if (!is_loopback(address.host) && address.token.size() < 32) {
    throw Error(what_ + " listens on " + address.host + ", beyond this machine: it needs a token");
  }
  address_ = std::move(address);
}

void PageGuard::install(httplib::Server& server) {
  server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    const PageAddress& a = address_;
    const std::string port = ":" + std::to_string(a.port);
    const std::string host = req.get_header_value("Host");
    const bool known_host = host == "127.0.0.1" + port || host == "localhost" + port || host == "[::1]" + port ||
                            host == host_for_url(a.host) + port;
    if (!known_host && !is_wildcard(a.host)) {
      send_error(res, 403, what_ + " answers requests for " + host_for_url(a.host) + port + " only, not for '" + host + "'");
      return httplib::Server::HandlerResponse::Handled;
    }
    if (!a.token.empty()) {
      const std::string cookie = cookie_name(a.port);
      if (req.has_param("token") && same_secret(req.get_param_value("token"), a.token)) {
        res.set_header("Set-Cookie", cookie + "=" + a.token + "; Path=/; HttpOnly; SameSite=Strict");
      } else if (!same_secret(cookie_value(req.get_header_value("Cookie"), cookie), a.token)) {
        send_error(res, 403, what_ + " needs the token printed when it started: open the URL with ?token=...");
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    if (changes_state(req.method)) {
      const std::string origin = req.get_header_value("Origin");
      if (!origin.empty() && origin != "http://" + host) {
        send_error(res, 403, what_ + " takes orders from its own page only, not from " + origin);
        return httplib::Server::HandlerResponse::Handled;
      }
      if (req.get_header_value("Content-Type").rfind("application/json", 0) != 0) {
        send_error(res, 415, what_ + " takes JSON only (Content-Type: application/json)");
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  // httplib calls this for every status >= 400; only bodiless ones get a line here.
  server.set_error_handler(httplib::Server::HandlerWithResponse([this](const httplib::Request& req,
                                                                        httplib::Response& res) {
    if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    const std::string message = res.status == 404 ? "no such page or API route: " + req.method + " " + req.path
                                                  : what_ + " answered HTTP " + std::to_string(res.status) + " to " +
                                                        req.method + " " + req.path;
    send_error(res, res.status, message);
    return httplib::Server::HandlerResponse::Handled;
  }));
  server.set_exception_handler([this](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown error";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    send_error(res, 500, what_ + " failed on " + req.method + " " + req.path + ": " + what);
  });
}

}  // namespace mtg::web
