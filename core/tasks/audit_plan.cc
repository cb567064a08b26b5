#include "core/tasks/audit_plan.h"

#include <algorithm>
#include <map>

#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/tasks/lookalike_aid.h"
#include "core/tasks/referring.h"
#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/rng.h"

namespace mtg::tasks {
namespace {

// An item's model: its name without the instance number ("book_01" of "book_01_37").
std::string item_model(const std::string& name) {
  const auto cut = name.find_last_of('_');
  return cut == std::string::npos ? name : name.substr(0, cut);
}

// The placement keys offered in `s` (placing) that leave part `part`'s goal met: what a person
// may answer to "which key does what the task says?", in the order offered, space-separated.
std::string placing_keys(const graph::SceneGraph& g, const episode::WorldState& s, const episode::AtomicGoal& part,
                         const TaskOptions& options, const episode::TaskConstraints& constraints) {
  episode::RuleOptions rules = options.rules;
  rules.step_limit = 1 << 20;
  std::string out;
  for (const episode::ActionOption& option : episode::action_space(g, s, rules)) {
    if (option.key == "0") continue;
    episode::WorldState trial = s;
    if (!episode::apply_action(g, trial, option.key, constraints, rules).applied) continue;
    if (episode::goal_satisfied(g, trial, part, options.goals)) out += (out.empty() ? "" : " ") + option.key;
  }
  return out;
}

// How the text names `object` in part `part` (its reference's phrase, or its close-up under the
// aid kImage), else its noun.
std::string words_for(const graph::SceneGraph& g, const Task& task, int part, const std::string& role,
                      graph::ObjectId object, Ambiguity rule, episode::LookalikeAid aid) {
  for (const Identification& id : task.identify) {
    if (id.part == part && id.role == role && id.object == g.objects[object].name) {
      return named_as(id, task.identify, aid);
    }
  }
  return "the " + noun_of(g.objects[object], rule);
}

}  // namespace

std::vector<const Task*> sample_for_audit(const std::vector<Task>& tasks, int per_level, std::uint64_t seed,
                                          const std::string& scene) {
  // Per level, tasks grouped by where their item comes from and what it is (Level 4: by
  // template), and the draw taken from the groups in turn: a few crowded platforms would
  // otherwise fill it.
  std::map<int, std::map<std::string, std::vector<const Task*>>> by_level;
  for (const Task& t : tasks) {
    if (!scene.empty() && t.scene != scene) continue;
    const std::string group = t.scene + "|" + (t.level == 4 ? t.template_id : t.source + "|" + item_model(t.item));
    by_level[t.level][group].push_back(&t);
  }
  std::vector<const Task*> out;
  for (auto& [level, groups] : by_level) {
    Rng rng(derive_seed(seed, fnv1a64("audit/L" + std::to_string(level))));
    std::vector<std::vector<const Task*>*> order;
    for (auto& [group, list] : groups) {
      std::sort(list.begin(), list.end(), [](const Task* a, const Task* b) { return a->id < b->id; });
      rng.shuffle(list);
      order.push_back(&list);
    }
    rng.shuffle(order);
    std::vector<const Task*> drawn;
    const auto wanted = static_cast<std::size_t>(std::max(0, per_level));
    for (std::size_t round = 0; drawn.size() < wanted; ++round) {
      bool any = false;
      for (const auto* list : order) {
        if (round < list->size() && drawn.size() < wanted) {
          drawn.push_back((*list)[round]);
          any = true;
        }
      }
      if (!any) break;
    }
    std::sort(drawn.begin(), drawn.end(), [](const Task* a, const Task* b) { return a->id < b->id; });
    out.insert(out.end(), drawn.begin(), drawn.end());
  }
  return out;
}

AuditPlan plan_audit(const graph::SceneGraph& g, const Task& task, const TaskOptions& options) {
  const episode::TaskGoal goal = episode::task_goal_from_json(g, task.goal);
  AuditPlan plan;
  episode::WorldState s = episode::initial_state(g, options.rules.numbering);
  plan.steps.push_back({s, 0});
  plan.observations.push_back({"", s, "The first observation", 0});
  int held_number = 0;
  episode::RuleOptions rules = options.rules;
  rules.step_limit = task.step_limit;
  const episode::TaskConstraints constraints{goal.protected_objects()};
  for (const std::string& key : task.oracle) {
    const episode::StepOutcome out = episode::apply_action(g, s, key, constraints, rules);
    if (!out.applied) throw Error("task " + task.id + ": its plan's key '" + key + "' does not play: " + out.hint);
    if (out.picked.valid()) held_number = std::stoi(key.substr(1));
    if (!s.held.valid()) held_number = 0;
    plan.steps.push_back({s, held_number});
    if (key[0] == 'l' && s.phase != episode::Phase::kDone) {
      plan.observations.push_back(
          {key, s,
           "After " + key + ": arriving at " + g.platforms[s.at_platform].name +
               (s.held.valid() ? " with the item in hand" : ""),
           static_cast<int>(plan.steps.size()) - 1});
    }
    if (key == "startplace") {
      plan.observations.push_back({key, s, "After startplace: choosing where to put the item on " +
                                               g.platforms[s.at_platform].name,
                                   static_cast<int>(plan.steps.size()) - 1});
    }
  }
  // Each object the text names is asked for where the agent arrives at its platform: an atomic
  // part's item at its source, its anchors at the destination with the item in hand.
  // holding: 1 with an item in hand, 0 without, -1 either.
  auto arrival = [&](graph::PlatformId platform, int holding, std::size_t from) -> int {
    for (std::size_t k = from; k < plan.observations.size(); ++k) {
      const episode::WorldState& at = plan.observations[k].state;
      if (at.at_platform == platform && (holding < 0 || at.held.valid() == (holding == 1))) return static_cast<int>(k);
    }
    return -1;
  };
  // Only what the view numbers is asked for (an anchor that cannot be picked, a tablet fixed to
  // its stand, carries no number; the person judges it with the task's validity).
  auto ask = [&](AuditQuestion q) {
    if (!q.truth.empty()) plan.questions.push_back(std::move(q));
  };
  if (goal.is_outcome) {
    for (std::size_t k = 0; k < task.identify.size(); ++k) {
      const Identification& id = task.identify[k];
      const graph::ObjectId object = g.find_object(id.object);
      const graph::PlatformId platform = g.find_platform(id.platform);
      const int at = arrival(platform, -1, 1);
      if (!object.valid() || at < 0) continue;
      ask({"o" + std::to_string(k) + ".object", "Which number is " + named_as(id, task.identify, options.rules.lookalike_aid) + "?", at,
           episode::object_key(g, plan.observations[static_cast<std::size_t>(at)].state, object)});
    }
    return plan;
  }
  std::size_t from = 1;
  for (std::size_t k = 0; k < goal.parts.size(); ++k) {
    const episode::AtomicGoal& part = goal.parts[k];
    const std::string p = "p" + std::to_string(k) + ".";
    const int source = arrival(part.source, 0, from);
    if (source < 0) throw Error("task " + task.id + ": its plan never arrives at part " + std::to_string(k) + "'s item");
    ask({p + "item",
                              "Which number is the item to move (" + words_for(g, task, static_cast<int>(k), "item", part.item, options.ambiguity,
                                               options.rules.lookalike_aid) +
                                  ")" + (goal.parts.size() > 1 ? " in part " + std::to_string(k + 1) : "") + "?",
                              source, episode::object_key(g, plan.observations[static_cast<std::size_t>(source)].state, part.item)});
    const int destination = arrival(part.platform, 1, static_cast<std::size_t>(source));
    from = static_cast<std::size_t>(std::max(source, destination)) + 1;
    if (destination < 0) continue;
    // Where it goes: the placing view as the agent sees it, and which key does what the task says.
    for (std::size_t at = static_cast<std::size_t>(destination) + 1; at < plan.observations.size(); ++at) {
      const AuditObservation& placing = plan.observations[at];
      if (placing.state.phase != episode::Phase::kPlacing || placing.state.at_platform != part.platform) continue;
      ask({p + "place",
           "Which key puts the item where the task says" +
               (goal.parts.size() > 1 ? " in part " + std::to_string(k + 1) : std::string()) + "?",
           static_cast<int>(at), placing_keys(g, placing.state, part, options, constraints)});
      from = std::max(from, at + 1);
      break;
    }
    const std::pair<graph::ObjectId, const char*> anchors[] = {{part.anchor, "anchor"}, {part.anchor2, "anchor2"}};
    for (const auto& [anchor, role] : anchors) {
      if (!anchor.valid()) continue;
      ask({p + role,
                                "Which number is the reference object " +
                                    words_for(g, task, static_cast<int>(k), role, anchor, options.ambiguity,
                                               options.rules.lookalike_aid) + "?",
                                destination,
                                episode::object_key(g, plan.observations[static_cast<std::size_t>(destination)].state, anchor)});
    }
  }
  return plan;
}

}  // namespace mtg::tasks
