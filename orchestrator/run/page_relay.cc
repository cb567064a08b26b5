#include "orchestrator/run/page_relay.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "core/util/error.h"

namespace mtg::orchestrator {
namespace {

int connect_unix(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof(addr.sun_path) - 1);
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::send(fd, data, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

}  // namespace

PageRelay::PageRelay(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string where = host + ":" + std::to_string(port);
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || found == nullptr) {
    throw Error("the play page cannot listen on " + where + " (unknown address)");
  }
  listen_fd_ = ::socket(found->ai_family, found->ai_socktype | SOCK_CLOEXEC, found->ai_protocol);
  const int one = 1;
  const bool ok = listen_fd_ >= 0 && ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) == 0 &&
                  ::bind(listen_fd_, found->ai_addr, found->ai_addrlen) == 0 && ::listen(listen_fd_, 64) == 0;
  ::freeaddrinfo(found);
  if (!ok) {
    const std::string why = std::strerror(errno);
    if (listen_fd_ >= 0) ::close(listen_fd_);
    throw Error("the play page cannot listen on " + where + " (" + why + "; taken? choose another with --port)");
  }
  // Short enough for sun_path (108 bytes) wherever the run folder is.
  socket_path_ = "/tmp/mtg-play-" + std::to_string(::getpid()) + "-" + std::to_string(port) + ".sock";
  ::unlink(socket_path_.c_str());
}

PageRelay::~PageRelay() {
  stop_ = true;
  if (acceptor_.joinable()) acceptor_.join();
  {
    const std::lock_guard lock(mutex_);
    for (const int fd : open_fds_) ::shutdown(fd, SHUT_RDWR);
  }
  for (auto& c : connections_) c.thread.join();
  if (listen_fd_ >= 0) ::close(listen_fd_);
  ::unlink(socket_path_.c_str());
}

void PageRelay::start() {
  acceptor_ = std::thread([this] { accept_loop(); });
}

void PageRelay::accept_loop() {
  while (!stop_) {
    pollfd p{listen_fd_, POLLIN, 0};
    if (::poll(&p, 1, 200) <= 0) continue;
    const int client = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    const std::lock_guard lock(mutex_);
    // A page long-polls: over an hour of play that is hundreds of connections, so the finished
    // ones are joined here rather than kept.
    std::erase_if(connections_, [](Connection& c) {
      if (!*c.done) return false;
      c.thread.join();
      return true;
    });
    open_fds_.push_back(client);
    auto done = std::make_shared<std::atomic<bool>>(false);
    connections_.push_back({std::thread([this, client, done] {
                              relay(client);
                              *done = true;
                            }),
                            done});
  }
}

void PageRelay::relay(int client) {
  const int page = connect_unix(socket_path_);
  if (page < 0) {
    // The human agent is not serving yet (the run is starting) or any more (it has ended).
    static const char kBody[] = "{\"error\":\"the play page is not being served now (the run is starting or has ended)\"}";
    const std::string reply = "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\nContent-Length: " +
                              std::to_string(sizeof(kBody) - 1) + "\r\nConnection: close\r\n\r\n" + kBody;
    write_all(client, reply.data(), reply.size());
  } else {
    {
      const std::lock_guard lock(mutex_);
      open_fds_.push_back(page);
    }
    // Both ways until either side is done; a long poll may sit here for its 20 s.
    pollfd fds[2] = {{client, POLLIN, 0}, {page, POLLIN, 0}};
    char buf[16384];
    bool open = true;
    while (open && !stop_) {
      if (::poll(fds, 2, 500) < 0 && errno != EINTR) break;
      for (int i = 0; i < 2 && open; ++i) {
        if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
        const ssize_t n = ::recv(fds[i].fd, buf, sizeof buf, 0);
        open = n > 0 && write_all(fds[1 - i].fd, buf, static_cast<std::size_t>(n));
      }
    }
  }
  const std::lock_guard lock(mutex_);
  for (const int fd : {client, page}) {
    if (fd < 0) continue;
    open_fds_.erase(std::remove(open_fds_.begin(), open_fds_.end(), fd), open_fds_.end());
    ::close(fd);
  }
}

}  // namespace mtg::orchestrator
