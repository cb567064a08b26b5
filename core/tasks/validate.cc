#include "core/tasks/validate.h"

#include <algorithm>
#include <cmath>

#include "core/episode/goals.h"
#include "core/episode/placement.h"
#include "core/episode/rules.h"
#include "core/tasks/atomic.h"
#include "core/tasks/referring.h"
#include "core/util/error.h"

namespace mtg::tasks {
namespace {

// Keys of one atomic part's plan: l<source>, o<k>, l<destination>, startplace, <target>.
constexpr std::size_t kKeysPerPart = 5;

// Whether `id`'s reference names exactly its object in `s`.
bool names_its_object(const graph::SceneGraph& g, const episode::WorldState& s, const Identification& id,
                      Ambiguity rule) {
  const graph::PlatformId platform = g.find_platform(id.platform);
  const graph::ObjectId object = g.find_object(id.object);
  if (!platform.valid() || !object.valid()) return false;
  const std::vector<graph::ObjectId> found = resolve(g, s, platform, id.reference, rule);
  return found.size() == 1 && found.front() == object;
}

// How a key of the anchor's own free spaces ends: "front-right of object 3" for a direction,
// " of object 3" (any side) for next to; "... of the " for an anchor without a number.
std::string placement_words(const graph::SceneGraph& g, const episode::WorldState& s, const episode::AtomicGoal& part) {
  const std::vector<graph::ObjectId> numbering = episode::numbered_on(g, s, s.at_platform);
  const auto it = std::find(numbering.begin(), numbering.end(), part.anchor);
  const std::string anchor = it == numbering.end() ? "the " : "object " + std::to_string(it - numbering.begin() + 1);
  const std::string side = part.type == episode::GoalType::kDirection ? graph::direction_name(part.direction) : "";
  return side + " of " + anchor;
}

}  // namespace

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

episode::WorldState start_of_part(const graph::SceneGraph& g, const Task& task, const TaskOptions& options, int part,
                                  bool holding) {
  const episode::TaskGoal goal = episode::task_goal_from_json(g, task.goal);
  if (goal.is_outcome) throw Error("task " + task.id + ": an outcome task has no parts to start");
  if (part < 0 || part >= static_cast<int>(goal.parts.size())) {
    throw Error("task " + task.id + " has no part " + std::to_string(part) + " (it has " +
                std::to_string(goal.parts.size()) + ")");
  }
  episode::WorldState s = episode::initial_state(g);
  episode::RuleOptions rules = options.rules;
  rules.step_limit = 1 << 20;
  const episode::TaskConstraints constraints{goal.protected_objects()};
  const std::size_t keys = kKeysPerPart * static_cast<std::size_t>(part) + (holding ? 2 : 0);
  for (std::size_t i = 0; i < keys && i < task.oracle.size(); ++i) {
    const auto out = episode::apply_action(g, s, task.oracle[i], constraints, rules);
    if (!out.applied) throw Error("task " + task.id + ": its plan's key '" + task.oracle[i] + "' does not play");
  }
  return s;
}

std::vector<std::string> audit_task(const graph::SceneGraph& g, const Task& task, const TaskOptions& options) {
  std::vector<std::string> problems;
  auto fail = [&](const std::string& what) { problems.push_back(task.id + ": " + what); };
  const PlayResult played = play_task(g, task, options);
  if (!played.success) fail("the oracle plan fails: " + played.failure);
  episode::TaskGoal goal;
  try {
    goal = episode::task_goal_from_json(g, task.goal);
  } catch (const Error& e) {
    fail(e.what());
    return problems;
  }
  const episode::WorldState initial = episode::initial_state(g);
  if (episode::task_goal_satisfied(g, initial, goal, options.goals)) fail("a do-nothing agent meets the goal");
  if (goal.is_outcome) {
    if (episode::outcome_satisfied(g, initial, goal.outcome, options.goals)) fail("the outcome holds at the start");
    for (const Identification& id : task.identify) {
      if (!names_its_object(g, initial, id, options.ambiguity)) fail("'" + id.phrase + "' does not name " + id.object);
    }
    return problems;
  }
  if (task.oracle.size() != kKeysPerPart * goal.parts.size() + 1) {
    fail("the oracle plan does not have " + std::to_string(kKeysPerPart) + " keys per part");
    return problems;
  }
  // Step through the parts: each must be worth asking and nameable where it starts, fit, and put
  // its item where the task says.
  episode::WorldState s = initial;
  episode::RuleOptions rules = options.rules;
  rules.step_limit = 1 << 20;
  const episode::TaskConstraints constraints{goal.protected_objects()};
  for (std::size_t k = 0; k < goal.parts.size(); ++k) {
    const episode::AtomicGoal& part = goal.parts[k];
    const std::string which = "part " + std::to_string(k) + ": ";
    if (episode::goal_met_from_any_side(g, s, part, options.goals)) fail(which + "its goal holds when it starts");
    episode::WorldState held = s;
    episode::pick(g, held, part.item);
    for (const Identification& id : task.identify) {
      if (id.part != static_cast<int>(k)) continue;
      const bool ok = names_its_object(g, s, id, options.ambiguity) &&
                      (id.role == "item" || names_its_object(g, held, id, options.ambiguity));
      if (!ok) fail(which + "'" + id.phrase + "' does not name " + id.object);
    }
    if (episode::stack_height(g, s, part.item) > g.platforms[part.platform].clearance) {
      fail(which + "the item with what rests on it is taller than the destination's clearance");
    }
    for (std::size_t i = 0; i < kKeysPerPart; ++i) {
      const std::string& key = task.oracle[kKeysPerPart * k + i];
      // A direction's key is offered in the task's own words (that side of that object), and a
      // next-to's as one of that object's own free spaces.
      const bool worded_goal = part.type == episode::GoalType::kDirection || part.type == episode::GoalType::kAround;
      if (i + 1 == kKeysPerPart && worded_goal) {
        const std::string wanted = placement_words(g, s, part);
        // "of object 1" must not pass for "of object 12"; an anchor with no number (the TV box)
        // is named in words after "of the ".
        const bool numbered = !wanted.ends_with("the ");
        bool worded = false;
        const auto offered = episode::action_space(g, s, rules);
        auto says = [&](const episode::ActionOption& option) {
          return numbered ? option.description.ends_with(wanted) : option.description.find(wanted) != std::string::npos;
        };
        for (const episode::ActionOption& option : offered) {
          if (option.key != key) continue;
          worded = says(option);
          break;
        }
        if (!worded) fail(which + "the key '" + key + "' is not offered as '" + wanted + "'");
        // "Next to X": a person may pick any of X's own free spaces; each that puts the item down
        // must put it where the goal holds (one the item does not fit in is refused by the rules,
        // and the person picks again).
        for (const episode::ActionOption& option : offered) {
          if (part.type != episode::GoalType::kAround || option.key == key || !says(option)) continue;
          episode::WorldState trial = s;
          if (!episode::apply_action(g, trial, option.key, constraints, rules).applied) continue;
          if (!episode::goal_satisfied(g, trial, part, options.goals)) {
            fail(which + "'" + option.description + "', one of the anchor's own spaces, is not next to it");
          }
        }
      }
      if (i + 1 == kKeysPerPart && part.type == episode::GoalType::kBetween) {
        // "Between X and Y": a person may pick a free space of X facing Y, or of Y facing X; each
        // that puts the item down must put it between them.
        const Eigen::Isometry2d X_PW = episode::platform_frame(g, s, s.at_platform).inverse();
        auto centre = [&](graph::ObjectId o) -> geom::Point2 {
          return geom::bounds(geom::transform(s.objects[o].footprint, X_PW)).center();
        };
        for (const episode::PlaceTarget& t : episode::place_targets(g, s, s.at_platform, static_cast<graph::Side>(s.side),
                                                                    rules.min_region_size)) {
          if (t.kind != episode::PlaceTarget::Kind::kObjectRegion || t.key == key) continue;
          if (t.anchor != part.anchor && t.anchor != part.anchor2) continue;
          if (!faces(t, centre(t.anchor), centre(t.anchor == part.anchor ? part.anchor2 : part.anchor))) continue;
          episode::WorldState trial = s;
          if (!episode::apply_action(g, trial, t.key, constraints, rules).applied) continue;
          if (!episode::goal_satisfied(g, trial, part, options.goals)) {
            fail(which + "free space " + t.key + ", facing the other anchor, is not between them");
          }
        }
      }
      if (!episode::apply_action(g, s, key, constraints, rules).applied) {
        fail(which + "'" + key + "' is not applied");
        return problems;
      }
    }
    if (k >= task.placements.size()) {
      fail(which + "no stored placement");
      continue;
    }
    const Eigen::Vector3d now = s.objects[part.item].position;
    if ((task.placements[k].position - now).norm() > 1e-6) fail(which + "the item does not land where the task says");
    if (episode::goal_margin(g, s, part, options.goals) < options.min_margin) {
      fail(which + "the placement lies less than " + std::to_string(options.min_margin) + " m inside its goal");
    }
  }
  for (std::size_t k = 0; k < goal.parts.size(); ++k) {
    if (episode::goal_margin(g, s, goal.parts[k], options.goals) < options.min_margin) {
      fail("part " + std::to_string(k) + ": no longer robustly met at the end");
    }
  }
  return problems;
}

}  // namespace mtg::tasks
