#include "agents/vlm/http_relay.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/util/error.h"

namespace mtg::vlm {
namespace {

constexpr std::uint32_t kMaxFrame = 256u << 20;  // 256 MiB: far above any model call

bool write_all(int fd, const void* data, std::size_t n) {
  const auto* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::send(fd, p, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

bool read_all(int fd, void* data, std::size_t n) {
  auto* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::recv(fd, p, n, 0);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

bool write_frame(int fd, const std::string& bytes) {
  const auto n = static_cast<std::uint32_t>(bytes.size());
  const unsigned char len[4] = {static_cast<unsigned char>(n >> 24), static_cast<unsigned char>(n >> 16),
                                static_cast<unsigned char>(n >> 8), static_cast<unsigned char>(n)};
  return write_all(fd, len, 4) && write_all(fd, bytes.data(), bytes.size());
}

bool read_frame(int fd, std::string& bytes) {
  unsigned char len[4];
  if (!read_all(fd, len, 4)) return false;
  const std::uint32_t n = (std::uint32_t{len[0]} << 24) | (std::uint32_t{len[1]} << 16) |
                          (std::uint32_t{len[2]} << 8) | std::uint32_t{len[3]};
  if (n > kMaxFrame) return false;
  bytes.resize(n);
  return n == 0 || read_all(fd, bytes.data(), n);
}

sockaddr_un address_of(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  if (path.size() >= sizeof(a.sun_path)) throw Error("HTTP relay: socket path too long: " + path);
  std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
  return a;
}

// Serves one call: the request in, http_post outside, the response out.
void serve(int fd) {
  std::string header, body;
  if (read_frame(fd, header) && read_frame(fd, body)) {
    HttpResponse response;
    try {
      const nlohmann::json h = nlohmann::json::parse(header);
      HttpRequest request;
      request.url = h.at("url").get<std::string>();
      request.headers = h.at("headers").get<std::vector<std::pair<std::string, std::string>>>();
      request.timeout_s = h.at("timeout_s").get<double>();
      request.connect_timeout_s = h.at("connect_timeout_s").get<double>();
      request.body = std::move(body);
      response = http_post_direct(request);
    } catch (const std::exception& e) {
      response.transport_error = std::string("HTTP relay: malformed request: ") + e.what();
    }
    const nlohmann::json out = {{"status", response.status},
                                {"headers", response.headers},
                                {"transport_error", response.transport_error},
                                {"elapsed_ms", response.elapsed_ms}};
    if (write_frame(fd, out.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace))) {
      write_frame(fd, response.body);
    }
  }
  ::close(fd);
}

}  // namespace

struct HttpRelayServer::State {
  int listen_fd = -1;
  std::atomic<bool> stopping{false};
  std::thread acceptor;
};

HttpRelayServer::HttpRelayServer() : state_(std::make_shared<State>()) {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/mtg-relay-XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) throw Error("HTTP relay: cannot make a folder for its socket in /tmp");
  dir_ = pattern;
  socket_path_ = dir_ + "/http.sock";
  state_->listen_fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const sockaddr_un a = address_of(socket_path_);
  if (state_->listen_fd < 0 || ::bind(state_->listen_fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) != 0 ||
      ::listen(state_->listen_fd, SOMAXCONN) != 0) {
    throw Error("HTTP relay: cannot listen on " + socket_path_ + ": " + std::strerror(errno));
  }
}

void HttpRelayServer::start() {
  std::shared_ptr<State> state = state_;
  state->acceptor = std::thread([state] {
    while (!state->stopping) {
      pollfd p{state->listen_fd, POLLIN, 0};
      if (::poll(&p, 1, 200) <= 0) continue;
      const int fd = ::accept4(state->listen_fd, nullptr, nullptr, SOCK_CLOEXEC);
      if (fd < 0) continue;
      std::thread(serve, fd).detach();  // a call ends within its own time-out
    }
  });
}

HttpRelayServer::~HttpRelayServer() {
  state_->stopping = true;
  if (state_->acceptor.joinable()) state_->acceptor.join();
  if (state_->listen_fd >= 0) ::close(state_->listen_fd);
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

HttpResponse relay_post(const std::string& socket_path, const HttpRequest& request, const std::atomic<bool>* cancel) {
  HttpResponse out;
  const auto started = std::chrono::steady_clock::now();
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  const sockaddr_un a = address_of(socket_path);
  if (fd < 0 || ::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) != 0) {
    out.transport_error = "HTTP relay " + socket_path + " does not answer: " + std::strerror(errno);
    if (fd >= 0) ::close(fd);
    return out;
  }
  const nlohmann::json header = {{"url", request.url},
                                 {"headers", request.headers},
                                 {"timeout_s", request.timeout_s},
                                 {"connect_timeout_s", request.connect_timeout_s}};
  std::string reply, body;
  bool ok = write_frame(fd, header.dump()) && write_frame(fd, request.body);
  // Wait for the answer, watching `cancel` (the relay's own call ends by its time-out).
  while (ok) {
    pollfd p{fd, POLLIN, 0};
    const int r = ::poll(&p, 1, 100);
    if (cancel != nullptr && cancel->load()) {
      out.transport_error = "cancelled";
      ::close(fd);
      return out;
    }
    if (r > 0) break;
    if (r < 0 && errno != EINTR) ok = false;
  }
  ok = ok && read_frame(fd, reply) && read_frame(fd, body);
  ::close(fd);
  if (!ok) {
    out.transport_error = "HTTP relay " + socket_path + " closed the connection";
    return out;
  }
  try {
    const nlohmann::json h = nlohmann::json::parse(reply);
    out.status = h.at("status").get<long>();
    out.headers = h.at("headers").get<std::map<std::string, std::string>>();
    out.transport_error = h.at("transport_error").get<std::string>();
    out.elapsed_ms = h.at("elapsed_ms").get<double>();
    out.body = std::move(body);
  } catch (const std::exception& e) {
    out.transport_error = std::string("HTTP relay: malformed response: ") + e.what();
    out.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  }
  return out;
}

}  // namespace mtg::vlm
