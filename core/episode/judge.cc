#include "core/episode/judge.h"

#include <algorithm>
#include <numeric>

namespace mtg::episode {
namespace {

// The stage of a part that reached `milestones` of its first three.
Stage stage_of(int milestones) { return kStagesInOrder[milestones]; }

}  // namespace

EpisodeJudge::EpisodeJudge(const graph::SceneGraph& g, TaskGoal goal, int level, GoalOptions options)
    : g_(g), goal_(std::move(goal)), level_(level), options_(options), replica_(initial_state(g)) {
  const std::size_t n = goal_.parts.size();
  reached_.assign(n, 0);
  wrong_item_picks_.assign(n, 0);
  placed_elsewhere_.assign(n, false);
  placed_on_dest_.assign(n, false);
  for (const SetPredicate& p : goal_.outcome.all) held_at_start_.push_back(predicate_satisfied(g_, replica_, p, options_));
}

std::vector<JudgeEvent> EpisodeJudge::observe(const StateUpdate& u) {
  std::vector<JudgeEvent> events;
  if (done_) return events;
  apply_update(g_, replica_, u);
  steps_ = u.step;
  if (u.step > 0) {  // every update after the initial one answers an action
    invalid_ += u.invalid ? 1 : 0;
    invalid_run_ = u.invalid ? invalid_run_ + 1 : 0;
    format_errors_ += u.format_error ? 1 : 0;
    provider_error_ = provider_error_ || u.provider_error;
  }
  for (std::size_t k = 0; k < goal_.parts.size(); ++k) {
    const AtomicGoal& part = goal_.parts[k];
    if (u.picked.valid() && u.picked != part.item) wrong_item_picks_[k] += 1;
    for (const Placement& p : u.placed) {
      if (p.object != part.item) continue;
      (p.platform == part.platform ? placed_on_dest_ : placed_elsewhere_)[k] = true;
    }
    // Milestones 1-3 in order ("holding anything" at the source, as the paper counts it).
    bool advanced = true;
    while (advanced && reached_[k] < 3) {
      advanced = false;
      const int next = reached_[k] + 1;
      const bool hit = (next == 1 && u.at_platform == part.source) ||
                       (next == 2 && u.holding == part.item) ||
                       (next == 3 && u.holding == part.item && u.at_platform == part.platform);
      if (hit) {
        reached_[k] = next;
        advanced = true;
        static const char* kText[] = {"", "reached the source platform", "picked the item",
                                      "reached the destination with the item"};
        events.push_back({u.step, static_cast<int>(k), next, 0.0, kText[next]});
      }
    }
  }
  if (u.done) {
    done_ = true;
    end_reason_ = u.end_reason;
    for (std::size_t k = 0; k < goal_.parts.size(); ++k) {
      if (reached_[k] == 3 && goal_satisfied(g_, replica_, goal_.parts[k], options_)) {
        events.push_back({u.step, static_cast<int>(k), 4, 0.0, "placed the item as asked"});
      }
    }
  }
  const double ip = current_ip(done_);
  for (auto& e : events) e.ip = ip;
  return events;
}

double EpisodeJudge::current_ip(bool final) const {
  if (goal_.is_outcome) {
    if (!final || goal_.outcome.all.empty()) return 0.0;
    // Points for what the agent brought about: the predicates that did not hold at the start and
    // hold now, out of those plus every one that held at the start and was broken ("leave the
    // books where they are" earns nothing by itself, so doing nothing scores 0).
    int made = 0, asked = 0;
    for (std::size_t k = 0; k < goal_.outcome.all.size(); ++k) {
      const bool now = predicate_satisfied(g_, replica_, goal_.outcome.all[k], options_);
      if (!held_at_start_[k]) {
        ++asked;
        made += now ? 1 : 0;
      } else if (!now) {
        ++asked;
      }
    }
    return asked == 0 ? 0.0 : 100.0 * made / static_cast<double>(asked);
  }
  if (goal_.parts.empty()) return 0.0;
  double sum = 0.0;
  for (std::size_t k = 0; k < goal_.parts.size(); ++k) {
    sum += part_points(k, final && reached_[k] == 3 && goal_satisfied(g_, replica_, goal_.parts[k], options_));
  }
  return sum / static_cast<double>(goal_.parts.size());
}

double EpisodeJudge::part_points(std::size_t k, bool goal_holds) const {
  return 25.0 * (reached_[k] == 3 && goal_holds ? 4 : reached_[k]);
}

Verdict EpisodeJudge::verdict() const {
  Verdict v;
  v.steps = steps_;
  v.invalid_actions = invalid_;
  v.ip = current_ip(true);
  const bool goal_met = task_goal_satisfied(g_, replica_, goal_, options_);
  const bool ended_by_agent = end_reason_ == EndReason::kCallEnd;
  v.success = done_ && ended_by_agent && goal_met;
  // A part is done when the agent carried its item to the destination (milestone 3) and the
  // goal holds there now; only then may the stage say "placed".
  for (std::size_t k = 0; k < goal_.parts.size(); ++k) {
    const bool ok = reached_[k] == 3 && goal_satisfied(g_, replica_, goal_.parts[k], options_);  // false while held
    v.part_success.push_back(ok);
    v.part_ip.push_back(part_points(k, ok));
  }
  if (v.success) {
    v.stage = Stage::kDone;
    v.detail = "goal reached and call_end";
    return v;
  }
  // Stage: the first part that is not done decides (Level 3 fails at its first failing part).
  std::size_t failing = 0;
  while (failing < goal_.parts.size() && v.part_success[failing]) ++failing;
  const bool all_parts_done = failing == goal_.parts.size();
  if (goal_.is_outcome) {
    v.stage = goal_met ? Stage::kPlaced : (v.ip > 0 ? Stage::kDestination : Stage::kStart);
  } else if (all_parts_done) {
    v.stage = Stage::kPlaced;
  } else {
    v.stage = stage_of(reached_[failing]);
  }
  // Cause, from what stopped the agent most directly.
  const bool step_limit = end_reason_ == EndReason::kStepLimit;
  const Cause ran_out = step_limit ? Cause::kStepLimit : Cause::kEarlyEnd;
  if (provider_error_) {
    v.cause = Cause::kProviderError;
  } else if (steps_ > 0 && 2 * format_errors_ >= steps_) {
    v.cause = Cause::kFormatError;
  } else if (step_limit && invalid_run_ >= 3) {
    v.cause = Cause::kInvalidActionLoop;
  } else if (ended_by_agent && steps_ <= 1 && !goal_met) {
    v.cause = Cause::kEarlyEnd;  // its first action was the end: it never tried, whatever the task
  } else if (goal_met) {
    v.cause = Cause::kNoCallEnd;  // the goal held but the agent never called call_end
  } else if (goal_.is_outcome) {
    v.cause = step_limit ? Cause::kStepLimit : Cause::kOutcomeUnmet;
  } else if (all_parts_done) {
    // Every item is where it belongs, but the episode ended with something in hand.
    v.cause = ran_out;
  } else {
    const std::size_t k = failing;
    const int r = reached_[k];
    if (r == 0) {
      v.cause = Cause::kNavigation;
    } else if (r == 1) {
      v.cause = wrong_item_picks_[k] > 0 ? Cause::kWrongItem : ran_out;
    } else if (placed_on_dest_[k] && replica_.objects[goal_.parts[k].item].parent ==
                                         goal_.parts[k].platform) {
      v.cause = Cause::kWrongRegion;
    } else if (placed_elsewhere_[k]) {
      v.cause = Cause::kWrongPlatform;
    } else {
      v.cause = ran_out;
    }
  }
  v.detail = std::string("stage ") + to_string(v.stage) + ", cause " + to_string(v.cause) +
             (done_ ? std::string(", ended by ") + to_string(end_reason_) : std::string(", not ended"));
  return v;
}

}  // namespace mtg::episode
