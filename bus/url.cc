#include "bus/url.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "core/util/error.h"

namespace mtg::bus {

std::string default_url() {
  for (const char* var : {"MTG_LCM_URL", "LCM_DEFAULT_URL"}) {
    if (const char* v = std::getenv(var); v != nullptr && *v != '\0') return normalize_url(v);
  }
  return kDefaultUrl;
}

std::string normalize_url(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return url;
  if (url.find("recv_buf_size=") != std::string::npos) return url;
  return url + (url.find('?') == std::string::npos ? "?" : "&") + "recv_buf_size=4194304";
}

std::optional<UdpmAddress> parse_udpm(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return std::nullopt;
  UdpmAddress a;
  const std::string rest = url.substr(7);
  const auto query = rest.find('?');
  const std::string hostport = rest.substr(0, query);
  const auto colon = hostport.find(':');
  a.group = hostport.substr(0, colon);
  a.port = colon == std::string::npos ? 7667 : std::atoi(hostport.c_str() + colon + 1);
  in_addr parsed{};
  if (a.group.empty() || inet_pton(AF_INET, a.group.c_str(), &parsed) != 1 || a.port <= 0) {
    throw Error("malformed LCM URL '" + url + "' (expected udpm://<group>:<port>?<options>)");
  }
  if (query != std::string::npos) {
    std::stringstream options(rest.substr(query + 1));
    std::string kv;
    while (std::getline(options, kv, '&')) {
      if (kv.rfind("ttl=", 0) == 0) a.ttl = std::atoi(kv.c_str() + 4);
    }
  }
  return a;
}

std::string multicast_interface(const std::string& group) {
  in_addr target{};
  if (inet_pton(AF_INET, group.c_str(), &target) != 1) return "";
  // The calling thread's namespace: /proc/net is the main thread's, and a bus of a private
  // network (private_network.h) is made on a thread inside it.
  std::ifstream routes("/proc/self/task/" + std::to_string(::gettid()) + "/net/route");
  std::string line;
  std::getline(routes, line);  // header
  std::string best;
  int best_prefix = -1;
  while (std::getline(routes, line)) {
    std::stringstream fields(line);
    std::string iface, dest_hex, gateway_hex, flags, refcnt, use, metric, mask_hex;
    if (!(fields >> iface >> dest_hex >> gateway_hex >> flags >> refcnt >> use >> metric >>
          mask_hex)) {
      continue;
    }
    // /proc/net/route prints addresses as host-order hex of the network-order value.
    const auto dest = static_cast<std::uint32_t>(std::stoul(dest_hex, nullptr, 16));
    const auto mask = static_cast<std::uint32_t>(std::stoul(mask_hex, nullptr, 16));
    if ((target.s_addr & mask) != (dest & mask)) continue;
    const int prefix = __builtin_popcount(mask);
    if (prefix > best_prefix) {
      best_prefix = prefix;
      best = iface;
    }
  }
  return best_prefix > 0 || (best_prefix == 0 && !best.empty()) ? best : "";
}

void check_multicast_route(const std::string& url) {
  const auto udpm = parse_udpm(url);
  if (!udpm) return;
  const std::string iface = multicast_interface(udpm->group);
  const std::string fix =
      "run `ip route replace 224.0.0.0/4 dev lo` as root (scripts do this when run as root)";
  if (iface.empty()) {
    throw Error("no multicast route for " + udpm->group + ": " +
                (udpm->ttl == 0 ? fix
                                : "route it through the interface that faces the other hosts, e.g. `ip route add " +
                                      udpm->group + "/32 dev eth0` (docs/multihost.md)"));
  }
  if (udpm->ttl == 0 && iface != "lo") {
    throw Error("multicast group " + udpm->group + " is routed through " + iface +
                ", not lo: LCM would join the group on " + iface + "; " + fix);
  }
}

std::optional<TcpqAddress> parse_tcpq(const std::string& url) {
  if (url.rfind("tcpq://", 0) != 0) return std::nullopt;
  const std::string rest = url.substr(7);
  const std::string hostport = rest.substr(0, rest.find('?'));
  const auto colon = hostport.rfind(':');
  TcpqAddress a;
  a.host = hostport.substr(0, colon);
  a.port = colon == std::string::npos ? 7700 : std::atoi(hostport.c_str() + colon + 1);
  if (a.host.empty() || a.port <= 0 || a.port > 65535) {
    throw Error("malformed LCM URL '" + url + "' (expected tcpq://<hub host>:<port>)");
  }
  return a;
}

namespace {

// The IPv4 addresses of `host`, empty when the name does not resolve.
std::vector<sockaddr_in> resolve(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  std::vector<sockaddr_in> out;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0) return out;
  for (const addrinfo* a = found; a != nullptr; a = a->ai_next) {
    out.push_back(*reinterpret_cast<const sockaddr_in*>(a->ai_addr));
  }
  ::freeaddrinfo(found);
  return out;
}

// A connect that gives up after `timeout`: a firewall that drops packets would otherwise hold a
// blocking connect for the kernel's SYN retries (about two minutes).
bool connects(const sockaddr_in& address, std::chrono::milliseconds timeout) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  bool ok = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  if (!ok && errno == EINPROGRESS) {
    pollfd p{fd, POLLOUT, 0};
    int error = 0;
    socklen_t len = sizeof error;
    ok = ::poll(&p, 1, static_cast<int>(timeout.count())) == 1 &&
         ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &len) == 0 && error == 0;
  }
  ::close(fd);
  return ok;
}

}  // namespace

bool accepts_tcp(const std::string& host, int port, std::chrono::milliseconds timeout) {
  for (const sockaddr_in& a : resolve(host, port)) {
    if (connects(a, timeout)) return true;
  }
  return false;
}

void check_hub_reachable(const std::string& url, std::chrono::milliseconds patience) {
  const auto hub = parse_tcpq(url);
  if (!hub) return;
  if (resolve(hub->host, hub->port).empty()) {
    throw Error("the hub host '" + hub->host + "' of " + url + " does not resolve (a typo? use a name or address every host knows)");
  }
  const auto deadline = std::chrono::steady_clock::now() + patience;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (accepts_tcp(hub->host, hub->port, std::max(left, std::chrono::milliseconds(200)))) return;
    if (std::chrono::steady_clock::now() >= deadline) {
      throw Error("no LCM hub answers at " + url + ": start one there with `mtg hub --port " +
                  std::to_string(hub->port) + "`, or open TCP port " + std::to_string(hub->port) +
                  " to it (docs/multihost.md)");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

}  // namespace mtg::bus
