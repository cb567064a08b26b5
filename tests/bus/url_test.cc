#include "bus/url.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>

#include "core/util/error.h"

namespace mtg::bus {
namespace {

using ::testing::HasSubstr;

TEST(BusUrl, NormalizeAddsTheReceiveBufferToUdpmOnly) {
  EXPECT_EQ(normalize_url("udpm://239.255.76.67:7667?ttl=0"),
            "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  EXPECT_EQ(normalize_url("udpm://239.255.76.67:7667"),
            "udpm://239.255.76.67:7667?recv_buf_size=4194304");
  EXPECT_EQ(normalize_url("udpm://239.255.76.67:7667?recv_buf_size=1048576"),
            "udpm://239.255.76.67:7667?recv_buf_size=1048576");
  EXPECT_EQ(normalize_url("memq://"), "memq://");
}

TEST(BusUrl, ParseUdpm) {
  const auto a = parse_udpm("udpm://239.255.76.68:7700?ttl=1&recv_buf_size=4194304");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->group, "239.255.76.68");
  EXPECT_EQ(a->port, 7700);
  EXPECT_EQ(a->ttl, 1);
  EXPECT_FALSE(parse_udpm("memq://"));
  EXPECT_THROW(parse_udpm("udpm://not-an-address:1"), Error);
}

// `scripts/with-bus --isolated` gives this process its own namespace, so changing routes is safe here.
TEST(BusUrl, RouteCheckPassesOnLoAndExplainsTheFixWhenMissing) {
  EXPECT_EQ(multicast_interface("239.255.76.67"), "lo");
  EXPECT_NO_THROW(check_multicast_route(kDefaultUrl));
  ASSERT_EQ(std::system("ip route del 224.0.0.0/4 dev lo"), 0);
  try {
    check_multicast_route(kDefaultUrl);
    ADD_FAILURE() << "expected an error without the route";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("ip route replace 224.0.0.0/4 dev lo"));
  }
  ASSERT_EQ(std::system("ip route add 224.0.0.0/4 dev lo"), 0);
}

TEST(BusUrl, ParseTcpq) {
  const auto a = parse_tcpq("tcpq://head-node.cluster:7790");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->host, "head-node.cluster");
  EXPECT_EQ(a->port, 7790);
  EXPECT_EQ(parse_tcpq("tcpq://10.0.0.1")->port, 7700);
  EXPECT_FALSE(parse_tcpq(kDefaultUrl));
  EXPECT_THROW(parse_tcpq("tcpq://:7700"), Error);
  EXPECT_THROW(parse_tcpq("tcpq://host:99999"), Error);
}

// A hub that is not there is named with the fix; one that listens passes at once.
TEST(BusUrl, HubCheckNamesTheUrlAndTheFixWhenNothingListens) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  socklen_t len = sizeof a;
  ASSERT_EQ(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len), 0);
  const std::string url = "tcpq://127.0.0.1:" + std::to_string(ntohs(a.sin_port));
  try {
    check_hub_reachable(url, std::chrono::milliseconds(300));  // bound, not yet listening
    ADD_FAILURE() << "expected an error without a hub";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no LCM hub answers at " + url));
    EXPECT_THAT(e.what(), HasSubstr("mtg hub --port " + std::to_string(ntohs(a.sin_port))));
  }
  ASSERT_EQ(::listen(fd, 4), 0);
  EXPECT_NO_THROW(check_hub_reachable(url, std::chrono::milliseconds(0)));
  EXPECT_NO_THROW(check_hub_reachable(kDefaultUrl, std::chrono::milliseconds(0)));
  ::close(fd);
}

}  // namespace
}  // namespace mtg::bus
