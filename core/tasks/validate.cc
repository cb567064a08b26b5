#include "core/tasks/validate.h"

#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/util/error.h"

namespace mtg::tasks {

PlayResult play_task(const graph::SceneGraph& g, const Task& task, const TaskOptions& options) {
  PlayResult r;
  episode::TaskGoal goal;
  try {
    goal = episode::task_goal_from_json(g, task.goal);
  } catch (const Error& e) {
    r.failure = e.what();
    return r;
  }
  episode::WorldState s = episode::initial_state(g);
  episode::RuleOptions rules = options.rules;
  rules.step_limit = task.step_limit;
  const episode::TaskConstraints constraints{goal.protected_objects()};
  for (const std::string& key : task.oracle) {
    const episode::StepOutcome out = episode::apply_action(g, s, key, constraints, rules);
    ++r.steps;
    if (!out.applied) {
      r.failure = "step " + std::to_string(r.steps) + " '" + key + "' not applied: " + out.hint;
      return r;
    }
    if (out.done) break;
  }
  if (s.phase != episode::Phase::kDone) {
    r.failure = "the plan does not end the episode";
    return r;
  }
  r.success = episode::task_goal_satisfied(g, s, goal, options.goals);
  if (!r.success) r.failure = "goal not satisfied at the end";
  return r;
}

}  // namespace mtg::tasks
