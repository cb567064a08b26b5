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
  EXPECT_FALSE(parse_reply(std::string(200000, 'x'), kOffered).ok);
  EXPECT_FALSE(parse_reply("I see 3 books and 2 cups", kOffered).ok);  // numbers among words are no key
}

// A real key that is not offered now is read as that key (the step rules refuse it with the
// reason, as an invalid action); only a reply with no key at all is a format error.
TEST(ReplyParser, ReadsARealKeyThatIsNotOfferedAsThatKey) {
  for (const char* reply : {"l99", "o7", "Action: o7", "I pick o7 because it is the red cup", "```\n5\n```", "5"}) {
    const ParsedReply p = parse_reply(reply, kOffered);
    EXPECT_TRUE(p.ok) << reply;
    EXPECT_FALSE(p.offered) << reply;
  }
  EXPECT_EQ(parse_reply("I pick o7 because it is the red cup", kOffered).key, "o7");
  EXPECT_TRUE(parse_reply("o2", kOffered).offered);
  // Offered keys win over keys that are not offered.
  EXPECT_EQ(parse_reply("not o7 but o2", kOffered).key, "o2");
  EXPECT_FALSE(parse_reply("o7 or o8", kOffered).ok);  // two real keys, none offered: no guess
}

}  // namespace
}  // namespace mtg::episode
