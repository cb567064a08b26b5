#include "core/episode/rules.h"
#include "core/episode/state_delta.h"

#include <gmock/gmock.h>
#include <map>
#include <gtest/gtest.h>

#include "core/episode/goals.h"
#include "tests/support/graph_fixtures.h"

namespace mtg::episode {
namespace {

using ::testing::HasSubstr;

std::vector<std::string> keys(const std::vector<ActionOption>& options) {
  std::vector<std::string> out;
  for (const auto& o : options) out.push_back(o.key);
  return out;
}

class RulesTest : public ::testing::Test {
 protected:
  void SetUp() override { built_ = testing::two_tables(fx_); }
  const graph::SceneGraph& g() const { return built_.graph; }
  StepOutcome act(WorldState& s, const std::string& key) { return apply_action(g(), s, key, constraints_, options_); }

  testing::FixtureDataset fx_;
  testing::BuiltScene built_;
  TaskConstraints constraints_;
  RuleOptions options_;
};

TEST_F(RulesTest, ActionSpaceFollowsThePapersStates) {
  WorldState s = initial_state(g());
  ASSERT_EQ(g().navigable.size(), 2u);
  EXPECT_EQ(keys(action_space(g(), s, options_)), (std::vector<std::string>{"0", "l1", "l2"}));
  ASSERT_TRUE(act(s, "l1").applied);
  EXPECT_EQ(keys(action_space(g(), s, options_)),
            (std::vector<std::string>{"-1", "0", "o1", "o2", "o3", "l1", "l2"}));
  ASSERT_TRUE(act(s, "o2").applied);
  EXPECT_EQ(s.held, g().find_object("box_2"));
  EXPECT_EQ(keys(action_space(g(), s, options_)), (std::vector<std::string>{"-1", "0", "l1", "l2", "startplace"}));
  ASSERT_TRUE(act(s, "l2").applied);
  ASSERT_TRUE(act(s, "startplace").applied);
  // An empty platform: the nine cells and "anywhere".
  EXPECT_EQ(keys(action_space(g(), s, options_)),
            (std::vector<std::string>{"0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "999"}));
  ASSERT_TRUE(act(s, "5").applied);  // front part
  EXPECT_FALSE(s.held.valid());
  EXPECT_EQ(s.objects[g().find_object("box_2")].parent, g().navigable[1]);
  const auto end = act(s, "0");
  EXPECT_TRUE(end.done);
  EXPECT_EQ(end.end_reason, EndReason::kCallEnd);
  EXPECT_EQ(s.steps, 6);
}

// apply_action() checks a key without writing the action space's descriptions: in every state a
// walk through the fixture reaches, it must accept exactly the keys action_space() offers.
TEST_F(RulesTest, TheKeysAStepAcceptsAreTheOnesTheActionSpaceOffers) {
  const std::vector<std::string> probes = {"0",  "-1", "startplace", "o1", "o2", "o3", "o4",  "o0", "o01", "l0",
                                           "l1", "l2", "l3",         "l01", "l1x", "o-1", "x1", "1",  "999", "o99999999999999999999"};
  WorldState s = initial_state(g());
  int states = 0;
  for (const std::string step : {"l1", "-1", "o2", "l2", "startplace", "5", "l1", "o1", "l1", "startplace", "999"}) {
    const auto offered = keys(action_space(g(), s, options_));
    for (const std::string& key : probes) {
      WorldState trial = s;
      const bool listed = std::find(offered.begin(), offered.end(), key) != offered.end();
      EXPECT_EQ(act(trial, key).available, listed) << "key " << key << " after " << states << " steps";
    }
    ASSERT_TRUE(act(s, step).applied) << step;
    ++states;
  }
}

TEST_F(RulesTest, FrontPartIsTheCellFarthestFromTheRobot) {
  WorldState s = initial_state(g());
  for (const char* k : {"l1", "o1", "l2", "startplace", "5"}) ASSERT_TRUE(act(s, k).applied) << k;
  const auto box = g().find_object("box_1");
  AtomicGoal goal;
  goal.type = GoalType::kSurfacePart;
  goal.item = box;
  goal.source = g().navigable[0];
  goal.platform = g().navigable[1];
  goal.direction = 4;  // front
  EXPECT_TRUE(goal_satisfied(g(), s, goal));
  // The robot stood at the default side; the item is on the far half of the table from it.
  const graph::Platform& p = g().platforms[g().navigable[1]];
  const geom::Point2 robot = p.sides[static_cast<size_t>(p.default_side)].standing_point;
  const geom::Point2 item = geom::centroid(geom::Region{{s.objects[box].footprint}});
  const geom::Point2 centre = p.X_WP.translation();
  EXPECT_GT((item - robot).norm(), (centre - robot).norm());
}

// The convention the agent is told (direction_convention(), in the system prompt and the placing
// text) is the one the targets number and the judge applies, from every side the robot can use:
// "front" lands farther from the robot than "rear", "left" on its left, and only the named part
// holds for the judge.
TEST_F(RulesTest, TheDirectionConventionTheAgentIsToldIsTheOneTargetsAndJudgeUse) {
  EXPECT_THAT(direction_convention(), HasSubstr("front is the part farthest from you"));
  EXPECT_THAT(direction_convention(), HasSubstr("rear the part nearest you"));
  const auto box = g().find_object("box_1");
  const auto table = g().navigable[1];
  const graph::Platform& p = g().platforms[table];
  int sides_checked = 0;
  for (const graph::Side side : graph::kSides) {
    if (!p.sides[static_cast<size_t>(side)].usable()) continue;
    ++sides_checked;
    const geom::Point2 robot = p.sides[static_cast<size_t>(side)].standing_point;
    const geom::Point2 centre = p.X_WP.translation();
    const Eigen::Vector2d forward = (centre - robot).normalized();
    std::map<std::string, geom::Point2> landed;  // part name -> where the item's centre lands
    for (const auto& [key, name] : std::vector<std::pair<std::string, std::string>>{
             {"1", "rear"}, {"3", "left"}, {"5", "front"}, {"7", "right"}}) {
      WorldState s = initial_state(g());
      for (const char* k : {"l1", "o1", "l2"}) ASSERT_TRUE(act(s, k).applied) << k;
      while (s.side != static_cast<int>(side)) ASSERT_TRUE(act(s, "-1").applied);
      ASSERT_TRUE(act(s, "startplace").applied);
      const auto offered = action_space(g(), s, options_);
      const auto option = std::find_if(offered.begin(), offered.end(), [&](const ActionOption& a) { return a.key == key; });
      ASSERT_NE(option, offered.end());
      EXPECT_THAT(option->description, HasSubstr("the " + name + " part"));
      ASSERT_TRUE(act(s, key).applied);
      landed[name] = geom::centroid(geom::Region{{s.objects[box].footprint}});
      for (const auto& [dir, part] : std::vector<std::pair<int, std::string>>{{0, "rear"}, {2, "left"}, {4, "front"}, {6, "right"}}) {
        AtomicGoal goal{GoalType::kSurfacePart, box, g().navigable[0], table, {}, {}, dir};
        EXPECT_EQ(goal_satisfied(g(), s, goal), part == name) << "side " << graph::to_string(side) << ": placed "
                                                              << name << ", judged " << part;
      }
    }
    EXPECT_GT((landed["front"] - robot).dot(forward), (landed["rear"] - robot).dot(forward) + 0.1);
    const auto cross = [&](const geom::Point2& q) { return forward.x() * (q - robot).y() - forward.y() * (q - robot).x(); };
    EXPECT_GT(cross(landed["left"]), cross(landed["right"]) + 0.1) << "left is on the robot's left";
  }
  EXPECT_GE(sides_checked, 2);
}

// An item the episode never placed has no side to name directions from: a direction or part
// goal about it does not hold, whatever its position (a do-nothing agent wins nothing).
TEST_F(RulesTest, AnItemNeverPlacedMeetsNoDirectionGoal) {
  const WorldState s = initial_state(g());
  const auto box1 = g().find_object("box_1"), box3 = g().find_object("box_3");
  AtomicGoal left_of_3{GoalType::kDirection, box1, g().navigable[0], g().navigable[0], box3, {}, 2};
  EXPECT_FALSE(goal_satisfied(g(), s, left_of_3));
  EXPECT_TRUE(goal_met_from_any_side(g(), s, left_of_3));  // so no task asks for it
  AtomicGoal around_3{GoalType::kAround, box1, g().navigable[0], g().navigable[0], box3, {}, -1};
  EXPECT_FALSE(goal_met_from_any_side(g(), s, around_3));  // 0.5 m apart
}

TEST_F(RulesTest, BadAndUnavailableKeysCostAStepWithAHint) {
  WorldState s = initial_state(g());
  auto r = act(s, "banana");
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.hint, HasSubstr("not an action key"));
  r = act(s, "o1");  // valid key, but nothing to pick at the start
  EXPECT_TRUE(r.valid);
  EXPECT_FALSE(r.available);
  EXPECT_THAT(r.hint, HasSubstr("not available"));
  r = act(s, "l9");
  EXPECT_FALSE(r.available);
  EXPECT_EQ(s.steps, 3);
  EXPECT_EQ(s.phase, Phase::kStart);
}

TEST_F(RulesTest, StepLimitEndsTheEpisode) {
  options_.step_limit = 3;
  WorldState s = initial_state(g());
  act(s, "l1");
  act(s, "-1");
  const auto r = act(s, "l2");
  EXPECT_TRUE(r.done);
  EXPECT_EQ(r.end_reason, EndReason::kStepLimit);
  EXPECT_FALSE(act(s, "l1").applied);  // nothing happens after the end
}

TEST_F(RulesTest, RotateVisitsTheUsableSidesClockwise) {
  WorldState s = initial_state(g());
  act(s, "l1");
  const int first = s.side;
  std::vector<int> seen = {first};
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(act(s, "-1").applied);
    seen.push_back(s.side);
  }
  EXPECT_EQ(seen, (std::vector<int>{first, (first + 1) % 4, (first + 2) % 4, (first + 3) % 4}));
}

TEST_F(RulesTest, AnchorsCannotBePicked) {
  constraints_.protected_objects = {g().find_object("box_2")};
  WorldState s = initial_state(g());
  act(s, "l1");
  const auto r = act(s, "o2");
  EXPECT_FALSE(r.applied);
  EXPECT_THAT(r.hint, HasSubstr("must stay where it is"));
  EXPECT_FALSE(s.held.valid());
  EXPECT_TRUE(act(s, "o1").applied);
}

TEST(Rules, PlacesTooSmallForTheObjectAreRefusedAndThePlacingGoesOn) {
  testing::FixtureDataset fx;
  testing::add_table(fx, "table");
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_object_config("toy_plank", fx.add_box_mesh("plank", {0.35, 0.02, 0.1}));
  fx.add_scene("s", {{"object_instances",
                      {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                       testing::FixtureDataset::instance("toy_box", testing::hab(-0.2, 0, 0.74)),
                       testing::FixtureDataset::instance("toy_box", testing::hab(0.2, 0, 0.74)),
                       testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0)),
                       testing::FixtureDataset::instance("toy_plank", testing::hab(3, 0, 0.74))}}});
  const auto built = testing::build_fixture_scene(fx, "s");
  const graph::SceneGraph& g = built.graph;
  RuleOptions options;
  WorldState s = initial_state(g);
  for (const char* k : {"l2", "o1", "l1", "startplace"}) ASSERT_TRUE(apply_action(g, s, k, {}, options).applied) << k;
  int refused = 0, placed = 0;
  for (const auto& option : action_space(g, s, options)) {
    if (option.key == "0") continue;
    WorldState trial = s;
    const auto out = apply_action(g, trial, option.key, {}, options);
    (out.applied ? placed : refused) += 1;
    if (!out.applied) {
      EXPECT_THAT(out.hint, HasSubstr("does not fit"));
      EXPECT_EQ(trial.phase, Phase::kPlacing);  // still holding, still placing
      EXPECT_EQ(trial.held, s.held);
    } else {
      EXPECT_FALSE(trial.held.valid());
    }
  }
  EXPECT_GT(refused, 0);  // e.g. the 0.3 m gap between the boxes for a 0.35 m plank
  EXPECT_GT(placed, 0);
}

// The release's numbering (tasks before mtg-tasks/4): every state numbers 1..N afresh.
TEST_F(RulesTest, PerStateNumberingAppendsAPlacedItemAndShiftsTheOthers) {
  WorldState s = initial_state(g(), Numbering::kPerState);
  for (const char* k : {"l1", "o1", "startplace", "999"}) ASSERT_TRUE(act(s, k).applied) << k;
  const auto objects = numbered_on(g(), s, g().navigable[0]);
  ASSERT_EQ(objects.size(), 3u);
  EXPECT_EQ(objects.back(), g().find_object("box_1"));  // numbers shift after a place
  RuleOptions named;
  named.object_names = true;
  EXPECT_THAT(situation_text(g(), s, named), HasSubstr("object 3 box"));
  EXPECT_THAT(situation_text(g(), s, RuleOptions{}), HasSubstr("Objects 1 to 3 here can be picked up"));
  EXPECT_TRUE(state_delta(g(), s).numbered.empty());
  EXPECT_THAT(situation_text(g(), s, RuleOptions{}), ::testing::Not(HasSubstr("Numbers belong to this platform")));
}

// Stable numbering (issue 53): a picked item's number is retired, never given to another; an
// item set down takes the next number; the keys, the texts and a state's delta say so.
TEST_F(RulesTest, StableNumberingKeepsEachItemsNumberAndRetiresAPickedOnes) {
  WorldState s = initial_state(g());
  const auto before = numbered_on(g(), s, g().navigable[0]);
  ASSERT_EQ(before.size(), 3u);
  ASSERT_EQ(before[0], g().find_object("box_1"));
  for (const char* k : {"l1", "o1"}) ASSERT_TRUE(act(s, k).applied) << k;
  // While the box is held, the others keep 2 and 3, and 1 is not offered.
  std::vector<std::string> keys;
  ASSERT_TRUE(act(s, "startplace").applied);
  ASSERT_TRUE(act(s, "999").applied);
  const auto after = numbered_on(g(), s, g().navigable[0]);
  ASSERT_EQ(after.size(), 4u);
  EXPECT_FALSE(after[0].valid());
  EXPECT_EQ(after[1], before[1]);
  EXPECT_EQ(after[2], before[2]);
  EXPECT_EQ(after[3], before[0]);  // set down again: a new number, after the highest
  EXPECT_EQ(number_of(g(), s, before[0]), 4);
  EXPECT_EQ(object_key(g(), s, before[1]), "o2");
  for (const ActionOption& a : action_space(g(), s, RuleOptions{})) keys.push_back(a.key);
  EXPECT_THAT(keys, ::testing::IsSupersetOf({"o2", "o3", "o4"}));
  EXPECT_THAT(keys, ::testing::Not(::testing::Contains("o1")));
  RuleOptions named;
  named.object_names = true;
  EXPECT_THAT(situation_text(g(), s, named), HasSubstr("object 4 box"));
  EXPECT_THAT(situation_text(g(), s, RuleOptions{}), HasSubstr("Objects 2 to 4 here can be picked up"));
  EXPECT_THAT(situation_text(g(), s, RuleOptions{}),
              HasSubstr("Numbers belong to this platform: an object keeps its number while it stays here, the number "
                        "of an object taken away is not used again, and an object set down here gets the next new "
                        "number."));
  EXPECT_THAT(act(s, "o1").hint, HasSubstr("o1 is not available here: the objects here are 2 to 4"));
  // Another process rebuilds the numbers from the state's delta.
  const WorldState rebuilt = apply_delta(g(), state_delta(g(), s));
  EXPECT_EQ(numbered_on(g(), rebuilt, g().navigable[0]), after);
  ASSERT_TRUE(act(s, "o4").applied);
  EXPECT_EQ(s.held, before[0]);
}

}  // namespace
}  // namespace mtg::episode

namespace mtg::episode {
namespace {

// A real key the state does not offer is refused with the reason, as an invalid action; the
// reply it came from was read (it is not a format error).
TEST_F(RulesTest, AKeyNotOfferedNowIsRefusedWithTheReason) {
  WorldState s = initial_state(g());
  StepOutcome out = act(s, "o1");
  EXPECT_TRUE(out.valid);
  EXPECT_FALSE(out.available);
  EXPECT_THAT(out.hint, HasSubstr("o1 is not available here: you are not at a platform yet"));
  ASSERT_TRUE(act(s, "l2").applied);  // the empty table
  out = act(s, "o1");
  EXPECT_THAT(out.hint, HasSubstr("o1 is not available here: there is nothing to pick up on this platform"));
  EXPECT_THAT(act(s, "l9").hint, HasSubstr("l9 is not available here: the platforms are l1 to l2"));
  EXPECT_THAT(act(s, "startplace").hint, HasSubstr("your hand is empty"));
  EXPECT_THAT(act(s, "4").hint, HasSubstr("numbered places are chosen after startplace"));
  ASSERT_TRUE(act(s, "l1").applied);
  EXPECT_THAT(act(s, "o4").hint, HasSubstr("the objects here are 1 to 3"));
  ASSERT_TRUE(act(s, "o1").applied);
  EXPECT_THAT(act(s, "o2").hint, HasSubstr("your hand is full"));
  ASSERT_TRUE(act(s, "l2").applied);
  ASSERT_TRUE(act(s, "startplace").applied);
  EXPECT_THAT(act(s, "12").hint, HasSubstr("the numbered places here are 1, 2, 3, 4, 5, 6, 7, 8, 9"));
  EXPECT_THAT(act(s, "l1").hint, HasSubstr("you are placing the object in your hand"));
}

}  // namespace
}  // namespace mtg::episode
