#include "core/episode/transcript.h"

#include "core/util/error.h"

namespace mtg::episode {

StateUpdate make_update(const WorldState& s, const std::string& key, const StepOutcome& outcome) {
  StateUpdate u;
  u.step = s.steps;
  u.key = key;
  u.at_platform = s.at_platform;
  u.side = s.side;
  u.holding = s.held;
  u.picked = outcome.picked;
  if (outcome.placed.valid()) {
    const ObjectState& o = s.objects[outcome.placed];
    u.placed.push_back({outcome.placed, o.parent, o.position});
  }
  u.invalid = !outcome.valid || !outcome.available;
  u.done = outcome.done;
  u.end_reason = outcome.end_reason;
  return u;
}

EpisodeStep step_episode(const graph::SceneGraph& g, WorldState& s, const AgentAnswer& answer,
                         const TaskConstraints& constraints, const RuleOptions& rules) {
  EpisodeStep out;
  if (answer.provider_error) {
    ++s.steps;
    s.phase = Phase::kDone;
    out.update = make_update(s, "", StepOutcome{});
    out.update.invalid = false;
    out.update.provider_error = true;
    out.update.done = true;
    out.update.end_reason = EndReason::kAborted;
    return out;
  }
  const std::string key = answer.format_ok ? answer.key : std::string();
  out.outcome = apply_action(g, s, key, constraints, rules);
  out.update = make_update(s, key, out.outcome);
  out.update.format_error = !answer.format_ok;
  out.hint = answer.format_ok ? out.outcome.hint
                              : "could not read an action key from your reply; answer with one key";
  return out;
}

void apply_update(const graph::SceneGraph& g, WorldState& replica, const StateUpdate& u) {
  if (u.picked.valid() && replica.held != u.picked) pick(g, replica, u.picked);
  replica.at_platform = u.at_platform;
  replica.side = u.side;
  for (const Placement& p : u.placed) {
    MTG_DEMAND(replica.held == p.object, "placement of an object the replica does not hold");
    place_held(g, replica, p.platform, p.position.head<2>());
  }
  replica.steps = u.step;
  if (u.done) replica.phase = Phase::kDone;
}

}  // namespace mtg::episode
