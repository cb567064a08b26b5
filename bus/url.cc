#include "bus/url.h"

#include <arpa/inet.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

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
  std::ifstream routes("/proc/net/route");
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

}  // namespace mtg::bus
