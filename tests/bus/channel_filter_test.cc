// The kernel-side channel filter (bus/channel_filter.h): its program on a real UDP socket, and a
// udpm bus that attaches it, in this test's own network namespace; a bus in a private one.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <linux/sock_diag.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "bus/bus.h"
#include "bus/channel_filter.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "bus/private_network.h"
#include "bus/process/subprocess.h"
#include "bus/url.h"
#include "mtg/heartbeat_t.hpp"
#include "tests/support/process.h"

namespace mtg::bus {
namespace {

namespace fs = std::filesystem;

// A datagram as liblcm sends an unfragmented message: "LC02", a sequence number, the channel.
std::string short_message(const std::string& channel, const std::string& payload) {
  return std::string("LC02") + std::string("\0\0\0\7", 4) + channel + std::string(1, '\0') + payload;
}

// A receiving socket with the filter and a sender aimed at it, on loopback unicast.
class FilteredSocket {
 public:
  explicit FilteredSocket(const std::vector<std::string>& channels) {
    rx_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    tx_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(::bind(rx_, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    socklen_t len = sizeof to_;
    ::getsockname(rx_, reinterpret_cast<sockaddr*>(&to_), &len);
    const timeval wait{2, 0};
    ::setsockopt(rx_, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof wait);
    attach_socket_filter(rx_, channel_filter_program(channels));
  }
  ~FilteredSocket() {
    ::close(rx_);
    ::close(tx_);
  }
  /// Whether `datagram` got through the filter. A fragment (which always passes) follows it, so
  /// whatever arrives first says, without guessing how long the kernel might take.
  bool passes(const std::string& datagram) {
    const std::string marker = std::string("LC03") + std::string(16, '\7') + "end of this check";
    send(datagram);
    send(marker);
    std::string first = receive();
    if (first == marker) return false;
    EXPECT_EQ(first, datagram);
    EXPECT_EQ(receive(), marker);
    return true;
  }

 private:
  void send(const std::string& d) {
    EXPECT_EQ(::sendto(tx_, d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_),
              static_cast<ssize_t>(d.size()));
  }
  std::string receive() {
    std::string got(65536, '\0');
    const ssize_t n = ::recv(rx_, got.data(), got.size(), 0);
    EXPECT_GE(n, 0) << "nothing arrived within 2 s";
    got.resize(static_cast<std::size_t>(std::max<ssize_t>(n, 0)));
    return got;
  }

  int rx_ = -1, tx_ = -1;
  sockaddr_in to_{};
};

TEST(ChannelFilter, LetsThroughOnlyTheSubscribedChannels) {
  FilteredSocket s({"MTG_OBS", "A", "MTG_EPISODE_START"});
  EXPECT_TRUE(s.passes(short_message("MTG_OBS", "payload")));
  EXPECT_TRUE(s.passes(short_message("MTG_EPISODE_START", std::string(3000, 'x'))));
  EXPECT_FALSE(s.passes(short_message("MTG_ACT", "payload")));
  EXPECT_FALSE(s.passes(short_message("MTG_OB", "payload")));      // a prefix of a subscribed name
  EXPECT_FALSE(s.passes(short_message("MTG_OBSX", "payload")));    // a subscribed name as a prefix
  EXPECT_FALSE(s.passes(short_message("B", "")));
  // The shortest datagram of a subscribed channel (no payload): every load stays inside it.
  EXPECT_TRUE(s.passes(short_message("A", "")));
}

TEST(ChannelFilter, LetsThroughFragmentsAndWhatIsNotLcm) {
  FilteredSocket s({"MTG_OBS"});
  // Only the first fragment of a large message names its channel: every fragment passes.
  EXPECT_TRUE(s.passes(std::string("LC03") + std::string(16, '\1') + "data of fragment 3"));
  EXPECT_TRUE(s.passes("hello, not LCM at all"));
  EXPECT_FALSE(s.passes("LC"));  // too short to hold a magic: liblcm would discard it too
}

TEST(ChannelFilter, APatternSubscriptionLetsEverythingThrough) {
  ChannelFilter f;
  EXPECT_TRUE(f.add("MTG_OBS"));
  EXPECT_FALSE(f.add("MTG_OBS"));
  ASSERT_TRUE(f.program().has_value());
  EXPECT_TRUE(f.add(".*"));
  EXPECT_FALSE(f.program().has_value());
  EXPECT_FALSE(f.add("MTG_ACT"));
  EXPECT_TRUE(is_literal_channel("MTG_EPISODE_TRUTH"));
  EXPECT_FALSE(is_literal_channel("MTG_(OBS|ACT)"));
  EXPECT_FALSE(is_literal_channel(""));
}

std::uint32_t kernel_drops(int fd) {
  std::uint32_t info[SK_MEMINFO_VARS] = {};
  socklen_t len = sizeof info;
  EXPECT_EQ(::getsockopt(fd, SOL_SOCKET, SO_MEMINFO, info, &len), 0);
  return info[SK_MEMINFO_DROPS];
}

// On a real udpm bus: the subscriber's socket drops the channels it did not ask for in the
// kernel (its drop count grows by exactly those) and still gets its own.
TEST(ChannelFilter, AUdpmBusDropsUnsubscribedChannelsBeforeItsProcessWakes) {
  const int port = parse_udpm(kDefaultUrl)->port;
  Bus publisher(kDefaultUrl);
  Bus subscriber(kDefaultUrl);
  int got = 0;
  subscriber.subscribe<mtg::heartbeat_t>("T_WANTED", [&](const std::string&, const mtg::heartbeat_t&) { ++got; });
  ASSERT_TRUE(subscriber.filters_channels());
  const std::vector<OpenSocket> sockets = udp_sockets_on_port(port);
  ASSERT_EQ(sockets.size(), 1u);  // the subscriber's receive socket; the publisher never subscribed
  const std::uint32_t drops_before = kernel_drops(sockets.front().fd);

  mtg::heartbeat_t beat{};
  beat.header.schema_version = kSchemaVersion;
  for (int i = 0; i < 20; ++i) publisher.publish("T_UNWANTED", beat);
  publisher.publish("T_WANTED", beat);
  subscriber.handle_until([&] { return got == 1; }, 5000);
  EXPECT_EQ(got, 1);
  EXPECT_EQ(kernel_drops(sockets.front().fd) - drops_before, 20u);
}

// Channels subscribed one after another replace the filter; a pattern after them removes it (a
// worker's runtime bus subscribes the services' channels, then ".*" to forward everything).
TEST(ChannelFilter, LaterSubscriptionsWidenTheFilterAndAPatternRemovesIt) {
  Bus publisher(kDefaultUrl);
  Bus bus(kDefaultUrl);
  std::vector<std::string> got;
  auto note = [&](const std::string& channel, std::span<const std::uint8_t>, std::int64_t) { got.push_back(channel); };
  mtg::heartbeat_t beat{};
  auto publish_all = [&] {
    got.clear();
    for (const char* channel : {"T_ONE", "T_TWO", "T_THREE"}) publisher.publish(channel, beat);
    publisher.publish("T_END", beat);  // subscribed throughout: the last to arrive
    bus.handle_until([&] { return !got.empty() && got.back() == "T_END"; }, 5000);
  };
  bus.subscribe_raw("T_END", note);
  bus.subscribe_raw("T_ONE", note);
  ASSERT_TRUE(bus.filters_channels());
  publish_all();
  EXPECT_EQ(got, (std::vector<std::string>{"T_ONE", "T_END"}));
  bus.subscribe_raw("T_TWO", note);
  publish_all();
  EXPECT_EQ(got, (std::vector<std::string>{"T_ONE", "T_TWO", "T_END"}));
  bus.subscribe_raw(".*", note);
  EXPECT_FALSE(bus.filters_channels());
  publish_all();
  // Each subscription of a channel hears it: T_ONE and T_TWO twice, T_THREE now through ".*".
  EXPECT_EQ(std::count(got.begin(), got.end(), "T_THREE"), 1);
  EXPECT_EQ(std::count(got.begin(), got.end(), "T_ONE"), 2);
}

TEST(ChannelFilter, ARecorderPatternBusGetsEveryChannel) {
  Bus publisher(kDefaultUrl);
  Bus everything(kDefaultUrl);
  int got = 0;
  everything.subscribe_raw(".*", [&](const std::string& channel, std::span<const std::uint8_t>, std::int64_t) {
    if (channel.rfind("T_", 0) == 0) ++got;
  });
  EXPECT_FALSE(everything.filters_channels());
  mtg::heartbeat_t beat{};
  publisher.publish("T_ONE", beat);
  publisher.publish("T_TWO", beat);
  everything.handle_until([&] { return got == 2; }, 5000);
  EXPECT_EQ(got, 2);
}

// A ttl=0 bus is this host's alone: liblcm's socket is bound to 0.0.0.0:<port>, so a unicast
// datagram to the port (as one from another machine arrives) reached it before. Now the kernel
// drops it, for a bus filtering channels and for a recorder's ".*" bus, while the bus's own
// multicast still arrives. (The same from a real other host: MultiHostTest.DatagramsSprayed...)
TEST(ChannelFilter, AHostBusDropsUnicastToItsPortAndKeepsItsMulticast) {
  const int port = parse_udpm(kDefaultUrl)->port;
  Bus publisher(kDefaultUrl);
  Bus channels(kDefaultUrl);
  int by_channel = 0;
  channels.subscribe<mtg::heartbeat_t>("T_WANTED", [&](const std::string&, const mtg::heartbeat_t&) { ++by_channel; });
  Bus everything(kDefaultUrl);
  int all = 0;
  everything.subscribe_raw(".*", [&](const std::string& channel, std::span<const std::uint8_t>, std::int64_t) {
    if (channel == "T_WANTED") ++all;
  });
  const std::vector<OpenSocket> sockets = udp_sockets_on_port(port);
  ASSERT_EQ(sockets.size(), 2u);
  std::vector<std::uint32_t> drops_before;
  for (const OpenSocket& s : sockets) drops_before.push_back(kernel_drops(s.fd));

  mtg::heartbeat_t beat{};
  beat.header.schema_version = kSchemaVersion;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(beat.getEncodedSize()));
  beat.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const std::string forged = short_message("T_WANTED", std::string(bytes.begin(), bytes.end()));
  const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(::sendto(tx, forged.data(), forged.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to),
              static_cast<ssize_t>(forged.size()));
  }
  ::close(tx);
  publisher.publish("T_WANTED", beat);
  channels.handle_until([&] { return by_channel >= 1; }, 5000);
  everything.handle_until([&] { return all >= 1; }, 5000);
  channels.handle_once(200);
  everything.handle_once(200);
  EXPECT_EQ(by_channel, 1) << "only the bus's own multicast arrives";
  EXPECT_EQ(all, 1) << "only the bus's own multicast arrives";
  // Unicast goes to one socket of those bound to the port: five drops between the two.
  std::uint32_t dropped = 0;
  for (std::size_t i = 0; i < sockets.size(); ++i) dropped += kernel_drops(sockets[i].fd) - drops_before[i];
  EXPECT_EQ(dropped, 5u);
}

TEST(ChannelFilter, OnlyAHostBusProgramAsksWhereADatagramCameFrom) {
  ChannelFilter any;
  any.add(".*");
  EXPECT_EQ(any.program(), std::nullopt) << "a pattern on a bus between hosts: no filter at all";
  EXPECT_EQ(loopback_group_of("udpm://239.255.76.67:7667?ttl=1"), std::nullopt);
  const auto group = loopback_group_of(kDefaultUrl);
  ASSERT_TRUE(group.has_value());
  EXPECT_EQ(group->group, 0xefff4c43u);  // 239.255.76.67
  ChannelFilter host(group);
  EXPECT_TRUE(host.add(".*"));
  ASSERT_TRUE(host.program().has_value()) << "a host bus keeps its loopback rule under a pattern";
  EXPECT_EQ(host.program()->size(), 7u);  // interface, destination (load, compare, drop each), accept
}

// A worker's host bus (bus/private_network.h): a bus made in a private network namespace and a
// real process started inside hear each other; a bus of the host on the same group and port, and
// unicast to that port, reach neither, and the host never hears the process.
TEST(PrivateNetwork, ABusInsideHearsOnlyTheProcessesStartedInside) {
  if (::geteuid() != 0) GTEST_SKIP() << "as root: otherwise the test process itself would move into a user namespace";
  const auto network = PrivateNetwork::make();
  Bus inside(kDefaultUrl, network);
  Bus outside(kDefaultUrl);
  std::set<int> heard_inside, heard_outside;
  inside.subscribe<mtg::heartbeat_t>(kHeartbeat, [&](const std::string&, const mtg::heartbeat_t& m) { heard_inside.insert(m.pid); });
  outside.subscribe<mtg::heartbeat_t>(kHeartbeat, [&](const std::string&, const mtg::heartbeat_t& m) { heard_outside.insert(m.pid); });
  const fs::path log = fs::temp_directory_path() / ("private_network_" + std::to_string(::getpid()) + ".lcmlog");
  const pid_t recorder =
      process::spawn_process({testing::bin("mtg_recorder"), "--url", kDefaultUrl, log.string()}, "", SIGKILL, network.get());
  mtg::heartbeat_t forged{};
  forged.header.schema_version = kSchemaVersion;
  forged.pid = 424242;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(forged.getEncodedSize()));
  forged.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const std::string datagram = short_message(kHeartbeat, std::string(bytes.begin(), bytes.end()));
  const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(parse_udpm(kDefaultUrl)->port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!heard_inside.count(recorder) && std::chrono::steady_clock::now() < until) {
    outside.publish(kHeartbeat, forged);  // the host's own multicast on the same group and port
    ::sendto(tx, datagram.data(), datagram.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    inside.handle_once(50);
    outside.handle_once(0);
  }
  for (int i = 0; i < 10; ++i) {
    inside.handle_once(50);
    outside.handle_once(0);
  }
  ::close(tx);
  ::kill(recorder, SIGKILL);
  ::waitpid(recorder, nullptr, 0);
  fs::remove(log);
  EXPECT_TRUE(inside.filters_channels()) << "its receive socket, made inside, was found and filtered";
  EXPECT_TRUE(heard_inside.count(recorder)) << "the process started inside is heard inside";
  EXPECT_FALSE(heard_inside.count(424242)) << "nothing of the host reaches the bus inside";
  EXPECT_FALSE(heard_outside.count(recorder)) << "the host does not hear the process inside";
  EXPECT_TRUE(heard_outside.count(424242)) << "the host's own bus still works";
}

}  // namespace
}  // namespace mtg::bus
