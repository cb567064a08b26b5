#pragma once
// The episode judge (DESIGN.md §3 "Judge"): follows an episode's state updates and scores it.
//
// Success: the agent called call_end, nothing is held, and the task's goal holds (every part of
// a Level 3 sequence; the outcome predicates of Level 4) — real geometric tests for every goal
// type, including "around" and "between" which the release never checks. Reaching the goal and
// running out of steps is a failure ("no_call_end"), as in the paper.
//
// Intermediate points, per atomic part, matched in order along the history: (1) the robot at the
// item's source platform, (2) holding the item, (3) holding it at the destination platform,
// (4) the part's goal holds at the end. IP = 25 x matched; a Level 3 task averages its parts;
// a Level 4 task scores 100 x the share of its predicates that hold at the end.
//
// Every failure gets a stage (furthest milestone: start, source, picked, destination, placed)
// and a cause: provider_error, format_error, invalid_action_loop, navigation, wrong_item,
// wrong_platform, wrong_region, no_call_end, step_limit, early_end, outcome_unmet.

#include <string>
#include <vector>

#include "core/episode/goals.h"
#include "core/episode/outcomes.h"
#include "core/episode/transcript.h"

namespace mtg::episode {

struct JudgeEvent {
  int step = 0;
  int part = 0;       // sub-task index
  int milestone = 0;  // 1..4
  double ip = 0.0;    // episode IP so far
  std::string text;
};

struct Verdict {
  bool success = false;
  double ip = 0.0;
  Stage stage = Stage::kStart;
  Cause cause = Cause::kNone;
  int steps = 0;
  int invalid_actions = 0;
  std::vector<double> part_ip;
  std::vector<bool> part_success;
  std::string detail;
};

class EpisodeJudge {
 public:
  /// `goal` is the task's resolved goal; `level` its level (1..4).
  EpisodeJudge(const graph::SceneGraph& g, TaskGoal goal, int level, GoalOptions options = {});

  /// Feeds the next update (in step order); returns the milestones it completes.
  std::vector<JudgeEvent> observe(const StateUpdate& u);
  bool done() const { return done_; }
  /// The verdict once done (or now, as if the episode ended here with `end_reason`).
  Verdict verdict() const;

 private:
  double current_ip(bool final) const;
  /// 25 per milestone matched in order; 100 when all three are and the part's goal holds.
  double part_points(std::size_t k, bool goal_holds) const;

  const graph::SceneGraph& g_;
  TaskGoal goal_;
  int level_;
  GoalOptions options_;
  WorldState replica_;
  std::vector<bool> held_at_start_;  // per outcome predicate, in the initial state
  std::vector<int> reached_;           // per part: milestones matched in order (0..3)
  std::vector<int> wrong_item_picks_;  // per part: other items picked
  std::vector<bool> placed_elsewhere_; // per part: the item was put on another platform
  std::vector<bool> placed_on_dest_;   // per part: the item was put on its destination
  int steps_ = 0;
  int invalid_ = 0;
  int invalid_run_ = 0;  // consecutive invalid actions at the end
  int format_errors_ = 0;
  bool provider_error_ = false;
  bool done_ = false;
  EndReason end_reason_ = EndReason::kNone;
};

}  // namespace mtg::episode
