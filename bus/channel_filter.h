#pragma once
// A kernel-side channel filter for udpm buses (docs/bus.md "Who wakes for what").
//
// Every process on a udpm group gets every datagram: liblcm's receive thread wakes for each,
// reads it, and only then drops a channel nothing subscribed to. With five processes sharing two
// cores those wake-ups were a third of a run's CPU, and they are why two episodes in flight were
// not much faster than one. A classic BPF socket filter on liblcm's receive socket drops the
// unwanted datagrams in the kernel, before anyone wakes. It reads only the LCM wire format
// (magic, then the NUL-terminated channel), so the bus, its recordings and stock lcm-logger,
// lcm-spy and lcm-logplayer are untouched: they subscribe to everything and attach no filter.

#include <linux/filter.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace mtg::bus {

/// The only datagrams a bus of this host alone (ttl=0) takes, whatever their channel: those to
/// its group that arrive on the loopback interface, as this host's own multicast does. liblcm
/// binds its receive socket to 0.0.0.0:<port>, so without this a unicast datagram from another
/// machine to that port was delivered like a message of the bus (issue 45: a forged shutdown
/// stopped a worker's judge), and so was a datagram multicast to another group the host joined
/// on its network interface (the shared bus's) with the host bus's port.
struct LoopbackGroup {
  std::uint32_t group = 0;   // the IPv4 group, host byte order
  int loopback_ifindex = 0;  // the loopback interface of this network namespace
};
/// The loopback group of a ttl=0 udpm `url` in this network namespace; nullopt for another URL.
std::optional<LoopbackGroup> loopback_group_of(const std::string& url);

/// The program for a UDP socket (the UDP header at offset 0): with `only`, drops every datagram
/// but those of that loopback group, then accepts an unfragmented LCM message whose channel is one of `channels`, every
/// fragment of a fragmented message (only the first names its channel) and any other datagram
/// of 4 bytes or more (liblcm judges it); drops the rest. With `everything`, every admitted
/// datagram is accepted. The kernel counts what it drops as receive errors of the socket
/// (`sk_drops`) and of UDP (`InErrors`): on a filtered bus those counters no longer mean lost
/// messages.
std::vector<sock_filter> channel_filter_program(const std::vector<std::string>& channels,
                                                const std::optional<LoopbackGroup>& only = std::nullopt,
                                                bool everything = false);

/// Whether an LCM subscription string names exactly one channel (LCM reads it as a regex).
bool is_literal_channel(const std::string& subscription);

/// Attaches `program` to `fd`, replacing any filter. @throws mtg::Error with the reason.
void attach_socket_filter(int fd, const std::vector<sock_filter>& program);
/// Removes the filter of `fd`, if any.
void detach_socket_filter(int fd);

/// One open socket of this process: its descriptor and its inode (a descriptor may be reused).
struct OpenSocket {
  int fd = -1;
  unsigned long inode = 0;
  bool operator==(const OpenSocket&) const = default;
};
/// This process's UDP sockets bound to `port`, by descriptor (none when /proc cannot be read).
std::vector<OpenSocket> udp_sockets_on_port(int port);
/// Whether `socket` is still that socket (same inode) and still bound to `port`.
bool is_open_socket(const OpenSocket& socket, int port);

/// The subscriptions of one bus and the filter they make: literal channels are let through,
/// and one pattern (the recorder's ".*") lets everything through; a bus of this host alone
/// keeps its loopback rule whatever is subscribed.
class ChannelFilter {
 public:
  explicit ChannelFilter(std::optional<LoopbackGroup> only = std::nullopt) : only_(only) {}
  /// Whether only this host's own multicast is let in.
  bool host_only() const { return only_.has_value(); }
  /// Whether a subscription lets every channel through.
  bool everything() const { return everything_; }
  /// Notes a subscription; true when the set of channels let through changed.
  bool add(const std::string& subscription);
  /// The program to attach, or nullopt when everything must pass.
  std::optional<std::vector<sock_filter>> program() const;

 private:
  std::optional<LoopbackGroup> only_;
  std::vector<std::string> channels_;
  bool everything_ = false;
};

}  // namespace mtg::bus
