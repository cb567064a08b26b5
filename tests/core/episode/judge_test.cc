// The judge on transcripts played with the real rules on a small scene.

#include "core/episode/judge.h"

#include <gtest/gtest.h>

#include "core/episode/outcomes.h"
#include "core/episode/rules.h"
#include "core/episode/transcript.h"
#include "core/tasks/atomic.h"
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

}  // namespace
}  // namespace mtg::episode
