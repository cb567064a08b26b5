#include "core/episode/reply_parser.h"

#include <gtest/gtest.h>

namespace mtg::episode {
namespace {

const std::vector<std::string> kOffered = {"-1", "0", "o1", "o2", "l1", "l12", "startplace"};

TEST(ReplyParser, ReadsKeysOutOfTheUsualWrappings) {
  EXPECT_EQ(parse_reply("l12", kOffered).key, "l12");
  EXPECT_EQ(parse_reply("  `l12`.\n", kOffered).key, "l12");
  EXPECT_EQ(parse_reply("\"o2\"", kOffered).key, "o2");
  EXPECT_EQ(parse_reply("**startplace**", kOffered).key, "startplace");
  EXPECT_EQ(parse_reply("I will go to the rack.\nAction: l12", kOffered).key, "l12");
  EXPECT_EQ(parse_reply("```\nl1\n```\nbecause the cup is there", kOffered).key, "l1");
  EXPECT_EQ(parse_reply("-1", kOffered).key, "-1");
  EXPECT_EQ(parse_reply("o1 - the red cup, which matches the task", kOffered).key, "o1");
}

TEST(ReplyParser, RefusesToGuess) {
  EXPECT_FALSE(parse_reply("", kOffered).ok);
  EXPECT_EQ(parse_reply("   ", kOffered).why, "empty reply");
  EXPECT_FALSE(parse_reply("I think l1 or maybe o2", kOffered).ok);  // two keys, no marker
  EXPECT_EQ(parse_reply("banana", kOffered).why, "no offered action key in the reply");
  EXPECT_FALSE(parse_reply("l99", kOffered).ok);  // not offered
  EXPECT_FALSE(parse_reply(std::string(200000, 'x'), kOffered).ok);
}

}  // namespace
}  // namespace mtg::episode
