#include "bus/url.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace mtg::bus
