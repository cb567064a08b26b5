#include "bus/channel_filter.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <net/if.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>

#include "bus/url.h"
#include "core/util/error.h"

namespace mtg::bus {
namespace {

// LCM's UDP wire format (lcm/udpm_util.h): a short message is magic "LC02", a sequence number and
// the NUL-terminated channel, then the payload; a fragment is "LC03" with a longer header, and only
// fragment 0 carries the channel.
constexpr std::uint32_t kShortMagic = 0x4c433032;  // "LC02"
constexpr std::uint32_t kUdpHeader = 8;             // a UDP socket's filter sees the UDP header
constexpr std::uint32_t kChannelAt = kUdpHeader + 8;
constexpr std::uint32_t kAccept = 0xffffffff;       // keep the whole datagram
constexpr std::uint32_t kDrop = 0;
constexpr std::int32_t kIpDestinationAt = 16;  // in the IPv4 header (SKF_NET_OFF: from its start)

sock_filter stmt(std::uint16_t code, std::uint32_t k) { return BPF_STMT(code, k); }
sock_filter jump(std::uint16_t code, std::uint32_t k, std::uint8_t jt, std::uint8_t jf) {
  return BPF_JUMP(code, k, jt, jf);
}

// Accepts the datagram if its channel is `channel`, else falls through to what follows. The
// length test first keeps every load inside the datagram (a load past its end would drop it
// instead of trying the next channel).
void match_channel(const std::string& channel, std::vector<sock_filter>& p) {
  std::string wanted = channel;
  wanted.push_back('\0');
  std::vector<sock_filter> compare;
  std::size_t at = 0;
  for (; at + 4 <= wanted.size(); at += 4) {
    std::uint32_t word = 0;
    for (std::size_t i = 0; i < 4; ++i) word = (word << 8) | static_cast<std::uint8_t>(wanted[at + i]);
    compare.push_back(stmt(BPF_LD | BPF_W | BPF_ABS, kChannelAt + static_cast<std::uint32_t>(at)));
    compare.push_back(jump(BPF_JMP | BPF_JEQ | BPF_K, word, 0, 0));
  }
  for (; at < wanted.size(); ++at) {
    compare.push_back(stmt(BPF_LD | BPF_B | BPF_ABS, kChannelAt + static_cast<std::uint32_t>(at)));
    compare.push_back(jump(BPF_JMP | BPF_JEQ | BPF_K, static_cast<std::uint8_t>(wanted[at]), 0, 0));
  }
  // Block: [len, jge, compare..., ret accept]; every failed test skips to the block's end.
  const std::size_t block = 2 + compare.size() + 1;
  if (block >= 256) throw Error("channel name too long for a socket filter: " + channel);
  p.push_back(stmt(BPF_LD | BPF_W | BPF_LEN, 0));
  p.push_back(jump(BPF_JMP | BPF_JGE | BPF_K, kChannelAt + static_cast<std::uint32_t>(wanted.size()), 0,
                   static_cast<std::uint8_t>(block - 2)));
  for (std::size_t i = 0; i < compare.size(); ++i) {
    if (i % 2 == 1) compare[i].jf = static_cast<std::uint8_t>(compare.size() - i);  // to past the ret
    p.push_back(compare[i]);
  }
  p.push_back(stmt(BPF_RET | BPF_K, kAccept));
}

// The inode of `fd` when it is an IPv4 socket bound to `port`.
std::optional<unsigned long> inode_if_bound(int fd, int port) {
  struct stat st{};
  if (::fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) return std::nullopt;
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0 || addr.sin_family != AF_INET ||
      ntohs(addr.sin_port) != port) {
    return std::nullopt;
  }
  return static_cast<unsigned long>(st.st_ino);
}

}  // namespace

std::vector<sock_filter> channel_filter_program(const std::vector<std::string>& channels,
                                                const std::optional<LoopbackGroup>& only, bool everything) {
  std::vector<sock_filter> p;
  if (only) {
    // The packet type cannot tell them apart: looped-back multicast and unicast to 127.0.0.1 both
    // arrive as PACKET_HOST on lo. The interface and the destination address can.
    p.push_back(stmt(BPF_LD | BPF_W | BPF_ABS, static_cast<std::uint32_t>(SKF_AD_OFF + SKF_AD_IFINDEX)));
    p.push_back(jump(BPF_JMP | BPF_JEQ | BPF_K, static_cast<std::uint32_t>(only->loopback_ifindex), 1, 0));
    p.push_back(stmt(BPF_RET | BPF_K, kDrop));
    p.push_back(stmt(BPF_LD | BPF_W | BPF_ABS, static_cast<std::uint32_t>(SKF_NET_OFF + kIpDestinationAt)));
    p.push_back(jump(BPF_JMP | BPF_JEQ | BPF_K, only->group, 1, 0));
    p.push_back(stmt(BPF_RET | BPF_K, kDrop));
  }
  if (everything) {
    p.push_back(stmt(BPF_RET | BPF_K, kAccept));
    return p;
  }
  p.push_back(stmt(BPF_LD | BPF_W | BPF_ABS, kUdpHeader));  // the magic
  p.push_back(jump(BPF_JMP | BPF_JEQ | BPF_K, kShortMagic, 1, 0));
  p.push_back(stmt(BPF_RET | BPF_K, kAccept));  // a fragment, or not LCM
  // (liblcm's self-test on a new socket is over before the first filter goes on.)
  std::vector<std::string> names = channels;
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  for (const std::string& name : names) match_channel(name, p);
  p.push_back(stmt(BPF_RET | BPF_K, kDrop));
  if (p.size() > BPF_MAXINSNS) throw Error("too many channels for one socket filter");
  return p;
}

bool is_literal_channel(const std::string& subscription) {
  return !subscription.empty() && subscription.find_first_of(".[]{}()\\*+?|^$") == std::string::npos;
}

void attach_socket_filter(int fd, const std::vector<sock_filter>& program) {
  sock_fprog prog{};
  prog.len = static_cast<unsigned short>(program.size());
  prog.filter = const_cast<sock_filter*>(program.data());  // the kernel copies it
  if (::setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog) != 0) {
    throw Error(std::string("cannot attach the channel filter to the LCM socket: ") + std::strerror(errno));
  }
}

void detach_socket_filter(int fd) {
  const int unused = 0;
  ::setsockopt(fd, SOL_SOCKET, SO_DETACH_FILTER, &unused, sizeof unused);  // ENOENT: none attached
}

bool is_open_socket(const OpenSocket& socket, int port) { return inode_if_bound(socket.fd, port) == socket.inode; }

std::vector<OpenSocket> udp_sockets_on_port(int port) {
  std::vector<OpenSocket> out;
  DIR* dir = ::opendir("/proc/self/fd");
  if (dir == nullptr) return out;
  while (const dirent* e = ::readdir(dir)) {
    char* end = nullptr;
    const long fd = std::strtol(e->d_name, &end, 10);
    if (end == e->d_name || *end != '\0' || fd == ::dirfd(dir)) continue;
    const auto inode = inode_if_bound(static_cast<int>(fd), port);
    int type = 0;
    socklen_t len = sizeof type;
    if (!inode || ::getsockopt(static_cast<int>(fd), SOL_SOCKET, SO_TYPE, &type, &len) != 0 || type != SOCK_DGRAM) {
      continue;
    }
    out.push_back({static_cast<int>(fd), *inode});
  }
  ::closedir(dir);
  std::sort(out.begin(), out.end(), [](const OpenSocket& a, const OpenSocket& b) { return a.fd < b.fd; });
  return out;
}

bool ChannelFilter::add(const std::string& subscription) {
  if (everything_) return false;
  if (!is_literal_channel(subscription)) {
    everything_ = true;
    return true;
  }
  if (std::find(channels_.begin(), channels_.end(), subscription) != channels_.end()) return false;
  channels_.push_back(subscription);
  return true;
}

std::optional<std::vector<sock_filter>> ChannelFilter::program() const {
  if (everything_ && !only_) return std::nullopt;
  return channel_filter_program(channels_, only_, everything_);
}

std::optional<LoopbackGroup> loopback_group_of(const std::string& url) {
  const auto udpm = parse_udpm(url);
  if (!udpm || udpm->ttl != 0) return std::nullopt;
  in_addr group{};
  const unsigned lo = ::if_nametoindex("lo");
  if (::inet_pton(AF_INET, udpm->group.c_str(), &group) != 1 || lo == 0) return std::nullopt;
  return LoopbackGroup{ntohl(group.s_addr), static_cast<int>(lo)};
}

}  // namespace mtg::bus
