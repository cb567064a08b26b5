// Episode recordings between hosts (orchestrator/remote/episode_log.h): the event-log bytes read
// back by lcm::LogFile, chunks put back together in any order, and damage detected.

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <fstream>

#include "core/util/error.h"
#include "mtg/heartbeat_t.hpp"
#include "orchestrator/remote/episode_log.h"
#include "tests/support/fixture_dataset.h"

namespace mtg::orchestrator::remote {
namespace {

std::vector<LoggedEvent> sample_events() {
  std::vector<LoggedEvent> events;
  for (int i = 0; i < 5; ++i) {
    mtg::heartbeat_t hb{};
    hb.header.run_id = "r";
    hb.header.episode_id = i;
    hb.header.attempt = 2;
    hb.role = std::string(static_cast<std::size_t>(1000 * i), 'x');  // sizes 0..4000 bytes
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(hb.getEncodedSize()));
    hb.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    events.push_back({"MTG_CH" + std::to_string(i), 1000 + i, bytes});
  }
  return events;
}

TEST(EpisodeLog, BytesAreAnLcmEventLogAndTheHeaderIsReadWithoutTheType) {
  const auto events = sample_events();
  const auto bytes = encode_event_log(events);
  testing::FixtureDataset dir;
  const auto file = dir.root() / "slice.lcmlog";
  std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
  lcm::LogFile log(file.string(), "r");
  ASSERT_TRUE(log.good());
  int n = 0;
  for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent(), ++n) {
    EXPECT_EQ(ev->channel, events[static_cast<std::size_t>(n)].channel);
    EXPECT_EQ(ev->timestamp, events[static_cast<std::size_t>(n)].utime);
    const auto h = peek_header({static_cast<const std::uint8_t*>(ev->data), static_cast<std::size_t>(ev->datalen)});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->episode_id, n);
    EXPECT_EQ(h->attempt, 2);
  }
  EXPECT_EQ(n, 5);
  const auto back = decode_event_log(bytes, "slice");
  ASSERT_EQ(back.size(), events.size());
  EXPECT_EQ(back[4].data, events[4].data);
  const std::vector<std::uint8_t> cut(bytes.begin(), bytes.end() - 10);
  EXPECT_THROW(decode_event_log(cut, "slice"), Error);
}

TEST(EpisodeLog, ChunksInAnyOrderWithDuplicatesGiveTheLogBackMissingOrDamagedOnesDoNot) {
  const auto bytes = encode_event_log(sample_events());
  mtg::header_t h{};
  auto chunks = make_chunks(h, "r/1/0", bytes, 1024);
  ASSERT_EQ(chunks.size(), (bytes.size() + 1023) / 1024);
  std::reverse(chunks.begin(), chunks.end());
  ChunkAssembly a;
  for (std::size_t i = 0; i + 1 < chunks.size(); ++i) a.add(chunks[i]);
  a.add(chunks[0]);  // a resent chunk
  EXPECT_FALSE(a.complete());
  EXPECT_THROW(a.bytes(), Error);
  a.add(chunks.back());
  ASSERT_TRUE(a.complete());
  EXPECT_EQ(a.bytes(), bytes);

  ChunkAssembly damaged;
  auto bad = make_chunks(h, "r/1/0", bytes, 1024);
  bad[1].data[7] ^= 0x40;  // one flipped bit
  for (const auto& c : bad) damaged.add(c);
  EXPECT_THROW(damaged.bytes(), Error);

  ChunkAssembly empty;
  const auto none = make_chunks(h, "r/1/0", {}, 1024);
  ASSERT_EQ(none.size(), 1u);  // an empty recording still says so
  empty.add(none[0]);
  EXPECT_TRUE(empty.complete());
  EXPECT_TRUE(empty.bytes().empty());

  ChunkAssembly mixed;
  mixed.add(make_chunks(h, "r/1/0", bytes, 1024)[0]);
  EXPECT_THROW(mixed.add(make_chunks(h, "r/1/0", bytes, 512)[1]), Error);  // another cut of it
}

}  // namespace
}  // namespace mtg::orchestrator::remote
