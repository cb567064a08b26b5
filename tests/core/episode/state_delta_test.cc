// A world state survives the trip through its delta exactly (the renderer numbers items from the
// rebuilt state), and a delta naming something the scene lacks is a clear error. The bus leg
// (world_state_delta_t) is in tests/bus/roundtrip_test.cc. A state change between any two states
// (what Level 4's planner keeps of a move) gives its end state back exactly too.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/episode/state_change.h"
#include "core/episode/state_delta.h"
#include "core/util/error.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/same_world_state.h"

namespace mtg {
namespace {

using testing::expect_same_world_state;

TEST(StateDelta, AStateRoundTripsExactlyThroughPickAndPlace) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  const auto& g = built.graph;
  episode::WorldState s = episode::initial_state(g);
  EXPECT_TRUE(episode::state_delta(g, s).moved.empty());
  expect_same_world_state(episode::apply_delta(g, episode::state_delta(g, s)), s);
  expect_same_world_state(episode::apply_delta(g, {}), s);

  const graph::ObjectId box = g.platforms[g.navigable[0]].items.empty()
                      ? g.platforms[g.navigable[1]].items.front()
                      : g.platforms[g.navigable[0]].items.front();
  s.phase = episode::Phase::kAtPlatform;
  s.at_platform = g.navigable[0];
  s.side = 2;
  s.steps = 3;
  episode::pick(g, s, box);
  const episode::StateDelta holding = episode::state_delta(g, s);
  EXPECT_EQ(holding.held, g.objects[box].name);
  ASSERT_FALSE(holding.reordered.empty());  // the item left its platform's list
  expect_same_world_state(episode::apply_delta(g, holding), s);

  // Placed at an odd position on the other table: doubles must come back bit for bit.
  const graph::PlatformId other = g.navigable.back();
  const Eigen::Vector2d xy = episode::platform_frame(g, s, other).translation() + Eigen::Vector2d(0.1 / 3, -0.2 / 7);
  episode::place_held(g, s, other, xy);
  const episode::StateDelta placed = episode::state_delta(g, s);
  EXPECT_EQ(placed.numbered.size(), 2u);  // the numbers kept on both tables
  expect_same_world_state(episode::apply_delta(g, placed), s);

  // The release's numbering keeps none, and comes back as itself.
  episode::WorldState per_state = episode::initial_state(g, episode::Numbering::kPerState);
  episode::pick(g, per_state, box);
  EXPECT_TRUE(episode::state_delta(g, per_state).numbered.empty());
  expect_same_world_state(episode::apply_delta(g, episode::state_delta(g, per_state)), per_state);
}

TEST(StateChange, PlaysStepsAgainOnTheirStartStateBitForBit) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  const auto& g = built.graph;
  const auto replayed = [](episode::WorldState from, const episode::WorldState& to) {
    const episode::StateChange change = episode::change_between(from, to);
    episode::apply_change(from, change);
    return from;
  };
  episode::WorldState start = episode::initial_state(g);
  start.numbered = {};  // the numbering table as a state that never numbered has it: not sized yet
  EXPECT_TRUE(episode::change_between(start, start).objects.empty());
  expect_same_world_state(replayed(start, start), start);

  // Pick on one table, place at an odd position on the other: the item, both tables' lists and
  // numbers, the hand and the robot change; nothing else is kept.
  const graph::PlatformId here = g.navigable.front(), other = g.navigable.back();
  episode::WorldState moved = start;
  const graph::ObjectId box = g.platforms[here].items.empty() ? g.platforms[other].items.front()
                                                              : g.platforms[here].items.front();
  const graph::PlatformId from = moved.objects[box].parent;
  const graph::PlatformId to = from == here ? other : here;
  moved.phase = episode::Phase::kAtPlatform;
  moved.at_platform = from;
  moved.side = 1;
  moved.steps = 4;
  episode::pick(g, moved, box);
  const Eigen::Vector2d xy = episode::platform_frame(g, moved, to).translation() + Eigen::Vector2d(0.1 / 3, -0.2 / 7);
  episode::place_held(g, moved, to, xy);
  const episode::StateChange change = episode::change_between(start, moved);
  EXPECT_LE(change.objects.size(), 2u);  // the item (and what rests on it)
  EXPECT_EQ(change.children.size(), 2u);
  EXPECT_EQ(change.numbered.size(), 2u);
  expect_same_world_state(replayed(start, moved), moved);

  // From a state that is not the initial one, back where it was picked from.
  episode::WorldState back = moved;
  back.at_platform = to;
  episode::pick(g, back, box);
  episode::place_held(g, back, from, episode::platform_frame(g, back, from).translation());
  expect_same_world_state(replayed(moved, back), back);

  // Equal is not enough: a zero's sign is a difference of bits, and is carried.
  episode::WorldState signed_zero = moved;
  signed_zero.objects[box].bottom = moved.objects[box].bottom == 0.0 ? -0.0 : moved.objects[box].bottom;
  signed_zero.objects[box].position.x() = -signed_zero.objects[box].position.x();
  signed_zero.platform_offset[here] = -Eigen::Vector3d::Zero();
  const episode::StateChange sign = episode::change_between(moved, signed_zero);
  ASSERT_EQ(sign.offsets.size(), 1u);
  EXPECT_TRUE(std::signbit(replayed(moved, signed_zero).platform_offset[here].x()));
  EXPECT_EQ(sign.objects.size(), 1u);
}

TEST(StateDelta, ADeltaNamingUnknownThingsIsAClearError) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  const auto fails = [&](const episode::StateDelta& d, const std::string& what) {
    EXPECT_THAT([&] { episode::apply_delta(built.graph, d); },
                ::testing::ThrowsMessage<Error>(::testing::HasSubstr(what)));
  };
  episode::StateDelta held;
  held.held = "nobody";
  fails(held, "'held' names no object");
  episode::StateDelta at;
  at.at = "nowhere";
  fails(at, "'at' names no platform");
  episode::StateDelta side;
  side.side = 9;
  fails(side, "'side' must be -1..3");
  episode::StateDelta phase;
  phase.phase = static_cast<episode::Phase>(7);
  fails(phase, "'phase' must be 0..3");
  episode::StateDelta moved;
  moved.moved.push_back({"ghost", "", Eigen::Vector3d::Zero(), {}, 0.0, 0.0, -1});
  fails(moved, "'moved.object' names no object");
  episode::StateDelta twice = episode::state_delta(built.graph, episode::initial_state(built.graph));
  const std::string name = built.graph.objects.front().name;
  twice.moved.push_back({name, "", Eigen::Vector3d::Zero(), {}, 0.0, 0.0, -1});
  twice.moved.push_back({name, "", Eigen::Vector3d::Zero(), {}, 0.0, 0.0, -1});
  fails(twice, "'moved.object' names '" + name + "' twice");
  episode::StateDelta side_of_object;
  side_of_object.moved.push_back({name, "", Eigen::Vector3d::Zero(), {}, 0.0, 0.0, 7});
  fails(side_of_object, "'moved.placed_side' of '" + name + "' must be -1..3");
  const std::string platform = built.graph.platforms[built.graph.navigable.front()].name;
  episode::StateDelta numbering;
  numbering.numbering = static_cast<episode::Numbering>(5);
  fails(numbering, "'numbering' must be 0 (stable) or 1 (per_state), got 5");
  episode::StateDelta kept_per_state;
  kept_per_state.numbering = episode::Numbering::kPerState;
  kept_per_state.numbered.push_back({platform, {name}});
  fails(kept_per_state, "per_state numbering has none");
  episode::StateDelta ghost_number;
  ghost_number.numbered.push_back({platform, {"", "ghost"}});
  fails(ghost_number, "'numbered." + platform + "' names no object");
  episode::StateDelta numbered_twice;
  numbered_twice.numbered.push_back({platform, {name, "", name}});
  fails(numbered_twice, "numbers '" + name + "' twice");
  episode::StateDelta nothing_numbered;
  nothing_numbered.numbered.push_back({platform, {}});
  fails(nothing_numbered, "lists no number");
}

}  // namespace
}  // namespace mtg
