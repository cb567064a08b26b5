#pragma once
// LCM URLs and the loopback multicast check (toolchain-notes §4): every udpm URL carries
// recv_buf_size=4194304, and udpm is refused when the multicast route would go out of eth0.

#include <chrono>
#include <optional>
#include <string>

namespace mtg::bus {

inline constexpr const char* kDefaultUrl =
    "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304";

/// $MTG_LCM_URL, else $LCM_DEFAULT_URL, else kDefaultUrl; normalised.
std::string default_url();

/// Adds recv_buf_size=4194304 to a udpm URL that lacks it; other providers pass unchanged.
std::string normalize_url(const std::string& url);

struct UdpmAddress {
  std::string group;  // dotted quad
  int port = 0;
  int ttl = 0;
};

/// The group/port/ttl of a udpm URL, nullopt for other providers (memq://, file://).
/// @throws mtg::Error for a malformed udpm URL.
std::optional<UdpmAddress> parse_udpm(const std::string& url);

/// Name of the interface the kernel routes `group` through (longest-prefix match in
/// /proc/net/route); "" if there is no route at all.
std::string multicast_interface(const std::string& group);

/// For udpm URLs: throws mtg::Error with the fix when the group is not routed through lo
/// (ttl=0) or only through the default route (ttl>0). No-op for other providers.
void check_multicast_route(const std::string& url);

struct TcpqAddress {
  std::string host;  // name or dotted quad
  int port = 0;
};

/// The hub host and port of a tcpq URL, nullopt for other providers.
/// @throws mtg::Error for a malformed tcpq URL.
std::optional<TcpqAddress> parse_tcpq(const std::string& url);

/// Whether something accepts a TCP connection at host:port within `timeout` (a name is
/// resolved first).
bool accepts_tcp(const std::string& host, int port, std::chrono::milliseconds timeout);

/// For tcpq URLs: waits up to `patience` for the hub to accept a connection, then throws
/// mtg::Error naming the URL and the fix (at once for a host name that does not resolve). liblcm itself would only print "Unable to connect"
/// and fail later, at the first publish. No-op for other providers.
void check_hub_reachable(const std::string& url, std::chrono::milliseconds patience);

}  // namespace mtg::bus
