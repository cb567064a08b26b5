// The judge on transcripts played with the real rules on a small scene.

#include "core/episode/judge.h"

#include <gtest/gtest.h>

#include "core/episode/goals.h"
#include "core/episode/outcomes.h"
#include "core/episode/rules.h"
#include "core/episode/transcript.h"
#include "core/episode/world_state.h"
#include "core/tasks/atomic.h"
#include "core/util/error.h"
#include "tests/support/graph_fixtures.h"

namespace mtg::episode {
namespace {

class JudgeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    built_ = testing::two_tables(fx_);
    // Move box_1 from table_0 to the front part of the empty table_4.
    goal_.type = GoalType::kSurfacePart;
    goal_.item = g().find_object("box_1");
    goal_.source = g().navigable[0];
    goal_.platform = g().navigable[1];
    goal_.direction = 4;
  }
  const graph::SceneGraph& g() const { return built_.graph; }

  Verdict play(const std::vector<std::string>& keys, int step_limit = 15, TaskGoal* custom = nullptr) {
    TaskGoal task_goal;
    task_goal.parts = {goal_};
    if (custom != nullptr) task_goal = *custom;
    EpisodeJudge judge(g(), task_goal, static_cast<int>(task_goal.parts.size()) > 1 ? 3 : 1);
    WorldState s = initial_state(g());
    RuleOptions rules;
    rules.step_limit = step_limit;
    judge.observe(StateUpdate{});
    for (const std::string& key : keys) {
      if (judge.done()) break;
      AgentAnswer answer{key, key != "<garbage>", false};
      events_ += static_cast<int>(judge.observe(step_episode(g(), s, answer, {}, rules).update).size());
    }
    return judge.verdict();
  }

  testing::FixtureDataset fx_;
  testing::BuiltScene built_;
  AtomicGoal goal_;
  int events_ = 0;
};

TEST_F(JudgeTest, TheOraclePlanSucceedsWithFullPoints) {
  const Verdict v = play({"l1", "o1", "l2", "startplace", "5", "0"});
  EXPECT_TRUE(v.success);
  EXPECT_DOUBLE_EQ(v.ip, 100.0);
  EXPECT_EQ(v.stage, Stage::kDone);
  EXPECT_EQ(v.cause, Cause::kNone);
  EXPECT_EQ(v.steps, 6);
  EXPECT_EQ(events_, 4);  // the four milestones, as they happen
}

// A goal that held before the agent did anything (a hand-made or old task: the generator makes
// none) is not "placed" by an agent that picked another object and ended: the stage stops where
// the agent did, the cause says what it did wrong, and every judge (live, rejudge) agrees.
TEST_F(JudgeTest, AGoalThatAlreadyHeldIsNotPlacedByAnAgentThatNeverMovedItsItem) {
  goal_.type = GoalType::kSurface;
  goal_.platform = goal_.source;  // box_1 already stands there
  const Verdict v = play({"l1", "o2", "0"});
  EXPECT_FALSE(v.success);
  EXPECT_EQ(v.stage, Stage::kSource);
  EXPECT_EQ(v.cause, Cause::kWrongItem);
  EXPECT_EQ(v.part_success, (std::vector<bool>{false}));
  const Verdict again = play({"l1", "o2", "0"});
  EXPECT_EQ(again.detail, v.detail);
}

TEST_F(JudgeTest, WrongPartIsAWrongRegionAtTheDestination) {
  const Verdict v = play({"l1", "o1", "l2", "startplace", "1", "0"});  // the rear part
  EXPECT_FALSE(v.success);
  EXPECT_DOUBLE_EQ(v.ip, 75.0);
  EXPECT_EQ(v.stage, Stage::kDestination);
  EXPECT_EQ(v.cause, Cause::kWrongRegion);
}

TEST_F(JudgeTest, ReachingTheGoalWithoutCallEndFailsAsInThePaper) {
  const Verdict v = play({"l1", "o1", "l2", "startplace", "5", "-1"}, 6);
  EXPECT_FALSE(v.success);
  EXPECT_DOUBLE_EQ(v.ip, 100.0);
  EXPECT_EQ(v.stage, Stage::kPlaced);
  EXPECT_EQ(v.cause, Cause::kNoCallEnd);
}

TEST_F(JudgeTest, PickingAnotherItemIsAWrongItem) {
  const Verdict v = play({"l1", "o2", "0"});
  EXPECT_EQ(v.stage, Stage::kSource);
  EXPECT_EQ(v.cause, Cause::kWrongItem);
  EXPECT_DOUBLE_EQ(v.ip, 25.0);
}

TEST_F(JudgeTest, PuttingTheItemOnAnotherPlatformIsAWrongPlatform) {
  const Verdict v = play({"l1", "o1", "startplace", "999", "0"});
  EXPECT_EQ(v.stage, Stage::kPicked);
  EXPECT_EQ(v.cause, Cause::kWrongPlatform);
  EXPECT_DOUBLE_EQ(v.ip, 50.0);
}

TEST_F(JudgeTest, NeverReachingTheSourceIsNavigation) {
  const Verdict v = play({"l2", "0"});
  EXPECT_EQ(v.stage, Stage::kStart);
  EXPECT_EQ(v.cause, Cause::kNavigation);
  EXPECT_DOUBLE_EQ(v.ip, 0.0);
}

TEST_F(JudgeTest, EndingBeforeDoingAnythingIsAnEarlyEndNotNavigation) {
  const Verdict v = play({"0"});
  EXPECT_FALSE(v.success);
  EXPECT_EQ(v.steps, 1);
  EXPECT_EQ(v.stage, Stage::kStart);
  EXPECT_EQ(v.cause, Cause::kEarlyEnd);
}

TEST_F(JudgeTest, UnreadableRepliesAreFormatErrorsAndLoopsOfInvalidKeysAreNamed) {
  const Verdict format = play(std::vector<std::string>(15, "<garbage>"));
  EXPECT_EQ(format.cause, Cause::kFormatError);
  EXPECT_EQ(format.invalid_actions, 15);
  const Verdict loop = play({"l1", "o1", "l9", "l9", "l9", "l9"}, 6);
  EXPECT_EQ(loop.cause, Cause::kInvalidActionLoop);
  EXPECT_EQ(loop.stage, Stage::kPicked);
}

TEST_F(JudgeTest, ALevelThreeTaskAveragesItsParts) {
  AtomicGoal second = goal_;
  second.item = g().find_object("box_2");
  second.type = GoalType::kSurface;
  second.direction = -1;
  TaskGoal both;
  both.parts = {goal_, second};
  // Only the first part is done: 100 and 25 (the robot stood at the source), mean 62.5.
  const Verdict v = play({"l1", "o1", "l2", "startplace", "5", "l1", "0"}, 15, &both);
  EXPECT_FALSE(v.success);
  EXPECT_DOUBLE_EQ(v.ip, 62.5);
  ASSERT_EQ(v.part_success.size(), 2u);
  EXPECT_TRUE(v.part_success[0]);
  EXPECT_FALSE(v.part_success[1]);
}

TEST(Outcomes, EveryNameReadsBackAsItsValue) {
  for (int i = 0; i <= static_cast<int>(Cause::kInfrastructure); ++i) {
    const auto c = static_cast<Cause>(i);
    EXPECT_EQ(cause_from_string(to_string(c)), c) << to_string(c);
  }
  for (const Stage s : kStagesInOrder) EXPECT_EQ(stage_from_string(to_string(s)), s) << to_string(s);
  for (const EndReason r : {EndReason::kNone, EndReason::kCallEnd, EndReason::kStepLimit, EndReason::kAborted}) {
    EXPECT_EQ(end_reason_from_string(to_string(r)), r) << to_string(r);
  }
  EXPECT_FALSE(cause_from_string("wrong_itme").has_value());
  EXPECT_FALSE(stage_from_string("").has_value());
}

// The Level 4 set predicates on two_tables: box_1, box_2, box_3 on table_0 (x = -0.3, 0, 0.3),
// table_4 empty at x = 3. Each new predicate holds exactly when its words say.
TEST(OutcomePredicates, CountApartAndNearMeanWhatTheySay) {
  testing::FixtureDataset fx;
  const auto built = testing::two_tables(fx);
  const graph::SceneGraph& g = built.graph;
  const graph::ObjectId b1 = g.find_object("box_1"), b2 = g.find_object("box_2"), b3 = g.find_object("box_3");
  const graph::PlatformId t0 = g.navigable[0], t4 = g.navigable[1];
  WorldState s = initial_state(g);
  const auto holds = [&](const SetPredicate& p) { return predicate_satisfied(g, s, p); };
  using Op = SetPredicate::Op;
  const SetPredicate two_on_t0{Op::kCountOn, {b1, b2, b3}, {t0}, {}, 2, 2};
  const SetPredicate at_most_one_on_t0{Op::kCountOn, {b1, b2, b3}, {t0}, {}, 0, 1};
  const SetPredicate apart{Op::kApart, {b1, b3}, {}, {}};
  const SetPredicate b1_near_b2{Op::kAllNear, {b1}, {}, {b2}};
  const SetPredicate nothing_near_b2{Op::kNoneNear, {b1, b3}, {}, {b2}};
  EXPECT_FALSE(holds(two_on_t0));  // three stand there
  EXPECT_FALSE(holds(at_most_one_on_t0));
  EXPECT_FALSE(holds(apart));  // same table
  EXPECT_FALSE(holds(b1_near_b2)) << "0.3 m apart, 0.1 m boxes: a 0.2 m gap is more than 0.10 m";
  EXPECT_TRUE(holds(nothing_near_b2));
  // Move box_1 to table_4, far from everything.
  pick(g, s, b1);
  EXPECT_FALSE(holds(apart)) << "a held object stands nowhere";
  place_held(g, s, t4, {3.0, 0.0});
  EXPECT_TRUE(holds(two_on_t0));
  EXPECT_FALSE(holds(at_most_one_on_t0));
  EXPECT_TRUE(holds(apart));
  EXPECT_FALSE(holds(b1_near_b2)) << "on another table";
  // Put box_1 back beside box_2 (0.12 m centre to centre: a 0.02 m gap).
  pick(g, s, b1);
  place_held(g, s, t0, {0.12, 0.0});
  EXPECT_TRUE(holds(b1_near_b2));
  EXPECT_FALSE(holds(nothing_near_b2));
  EXPECT_FALSE(holds(apart));
  // Goals read back from their JSON with their counts; a count_on without them is refused.
  OutcomeGoal goal{{two_on_t0, apart, b1_near_b2, nothing_near_b2}};
  const OutcomeGoal back = outcome_goal_from_json(g, to_json(g, goal));
  ASSERT_EQ(back.all.size(), 4u);
  EXPECT_EQ(back.all[0].min, 2);
  EXPECT_EQ(back.all[0].max, 2);
  EXPECT_EQ(to_json(g, back), to_json(g, goal));
  nlohmann::json broken = to_json(g, goal);
  broken["all"][0].erase("max");
  EXPECT_THROW(outcome_goal_from_json(g, broken), Error);
  broken = to_json(g, goal);
  broken["all"][2].erase("objects2");
  EXPECT_THROW(outcome_goal_from_json(g, broken), Error);
}

}  // namespace
}  // namespace mtg::episode
