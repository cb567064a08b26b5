// A world state survives the trip through its JSON delta exactly (the renderer numbers items from
// the rebuilt state), and a delta naming something the scene lacks is a clear error.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/episode/state_json.h"
#include "core/util/error.h"
#include "tests/support/graph_fixtures.h"

namespace mtg {
namespace {

void expect_same(const episode::WorldState& a, const episode::WorldState& b) {
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].parent, b.objects[i].parent) << i;
    EXPECT_EQ(a.objects[i].position, b.objects[i].position) << i;
    EXPECT_EQ(a.objects[i].footprint, b.objects[i].footprint) << i;
    EXPECT_EQ(a.objects[i].bottom, b.objects[i].bottom) << i;
    EXPECT_EQ(a.objects[i].top, b.objects[i].top) << i;
    EXPECT_EQ(a.objects[i].placed_side, b.objects[i].placed_side) << i;
  }
  EXPECT_EQ(a.children, b.children);
  EXPECT_EQ(a.platform_offset, b.platform_offset);
  EXPECT_EQ(a.held, b.held);
  EXPECT_EQ(a.at_platform, b.at_platform);
  EXPECT_EQ(a.side, b.side);
  EXPECT_EQ(a.phase, b.phase);
  EXPECT_EQ(a.steps, b.steps);
}

TEST(StateJson, AStateRoundTripsExactlyThroughPickAndPlace) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  const auto& g = built.graph;
  episode::WorldState s = episode::initial_state(g);
  EXPECT_TRUE(episode::state_delta_to_json(g, s)["moved"].empty());
  expect_same(episode::state_from_delta_json(g, episode::state_delta_to_json(g, s)), s);

  const int box = g.platforms[static_cast<std::size_t>(g.navigable[0])].items.empty()
                      ? g.platforms[static_cast<std::size_t>(g.navigable[1])].items.front()
                      : g.platforms[static_cast<std::size_t>(g.navigable[0])].items.front();
  s.phase = episode::Phase::kAtPlatform;
  s.at_platform = g.navigable[0];
  s.side = 2;
  s.steps = 3;
  episode::pick(g, s, box);
  const nlohmann::json holding = episode::state_delta_to_json(g, s);
  EXPECT_EQ(holding["held"], g.objects[static_cast<std::size_t>(box)].name);
  expect_same(episode::state_from_delta_json(g, nlohmann::json::parse(holding.dump())), s);

  // Placed at an odd position on the other table: doubles must come back bit for bit.
  const int other = g.navigable.back();
  const Eigen::Vector2d xy = episode::platform_frame(g, s, other).translation() + Eigen::Vector2d(0.1 / 3, -0.2 / 7);
  episode::place_held(g, s, other, xy);
  expect_same(episode::state_from_delta_json(g, nlohmann::json::parse(episode::state_delta_to_json(g, s).dump())), s);
}

TEST(StateJson, ADeltaNamingUnknownThingsIsAClearError) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  EXPECT_THAT([&] { episode::state_from_delta_json(built.graph, {{"held", "nobody"}}); },
              ::testing::ThrowsMessage<Error>(::testing::HasSubstr("'held' names no object")));
  EXPECT_THAT([&] { episode::state_from_delta_json(built.graph, {{"at", "nowhere"}}); },
              ::testing::ThrowsMessage<Error>(::testing::HasSubstr("'at' names no platform")));
  EXPECT_THAT([&] { episode::state_from_delta_json(built.graph, {{"side", 9}}); },
              ::testing::ThrowsMessage<Error>(::testing::HasSubstr("'side' must be -1..3")));
  EXPECT_THAT([&] { episode::state_from_delta_json(built.graph, nlohmann::json::array()); },
              ::testing::ThrowsMessage<Error>(::testing::HasSubstr("expected a JSON object")));
}

}  // namespace
}  // namespace mtg
