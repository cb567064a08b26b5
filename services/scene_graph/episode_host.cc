#include "services/scene_graph/episode_host.h"

#include <cstdlib>
#include <sstream>

#include "bus/channels.h"
#include "bus/convert.h"
#include "core/episode/transcript.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/error_event_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/state_update_t.hpp"

namespace mtg::services {

FaultInjection FaultInjection::from_env() {
  FaultInjection f;
  const char* env = std::getenv("MTG_FAULTS");
  if (env == nullptr) return f;
  std::stringstream in(env);
  std::string item;
  while (std::getline(in, item, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string::npos) continue;
    const int step = std::atoi(item.c_str() + colon + 1);
    if (item.compare(0, colon, "drop_state") == 0) f.drop_state_step = step;
    if (item.compare(0, colon, "dup_state") == 0) f.duplicate_state_step = step;
  }
  return f;
}

EpisodeHost::EpisodeHost(bus::Bus& bus, bus::HeaderStamper& stamp, SceneCache& scenes, std::string run_id,
                         FaultInjection faults)
    : bus_(bus), stamp_(stamp), scenes_(scenes), run_id_(std::move(run_id)), faults_(faults) {
  bus_.subscribe<mtg::episode_start_t>(bus::kEpisodeStart, [this](const std::string&, const mtg::episode_start_t& m) {
    if (run_id_.empty() || m.header.run_id == run_id_) on_start(m);
  });
  bus_.subscribe<mtg::agent_action_t>(bus::episode_channel_regex(bus::EpisodeStream::kAction),
                                      [this](const std::string&, const mtg::agent_action_t& m) {
                                        if (run_id_.empty() || m.header.run_id == run_id_) on_action(m);
                                      });
}

void EpisodeHost::on_start(const mtg::episode_start_t& start) {
  const Key key{start.header.run_id, start.header.episode_id};
  const auto existing = episodes_.find(key);
  if (existing != episodes_.end() && existing->second.attempt >= start.header.attempt) return;  // duplicate
  try {
    Episode e;
    e.attempt = start.header.attempt;
    e.task = bus::from_message(start.task);
    e.graph = &scenes_.get(e.task.scene, start.data_dir);
    e.constraints.protected_objects = episode::task_goal_from_json(*e.graph, e.task.goal).protected_objects();
    e.rules = bus::episode_rules(start);
    e.state = episode::initial_state(*e.graph);
    e.render = start.render;
    episodes_[key] = std::move(e);
  } catch (const Error& err) {
    mtg::error_event_t ev{};
    ev.header = stamp_.next(start.header.episode_id, start.header.attempt, "error");
    ev.header.run_id = start.header.run_id;
    ev.source = stamp_.sender();
    ev.severity = "error";
    ev.message = "episode " + std::to_string(start.header.episode_id) + ": " + err.what();
    bus_.publish(bus::kError, ev);
    log::error(ev.message);
    return;
  }
  Episode& e = episodes_[key];
  // Step 0: the initial world for the judge, then the first observation for the agent.
  episode::StateUpdate initial;
  initial.side = -1;
  publish_state(key, e, initial);
  publish_observation(key, e);
}

void EpisodeHost::on_action(const mtg::agent_action_t& action) {
  const Key key{action.header.run_id, action.header.episode_id};
  const auto it = episodes_.find(key);
  if (it == episodes_.end()) return;
  Episode& e = it->second;
  if (action.header.attempt != e.attempt || action.step != e.state.steps ||
      e.state.phase == episode::Phase::kDone) {
    return;  // stale, duplicate or late: never applied twice
  }
  const episode::EpisodeStep step =
      episode::step_episode(*e.graph, e.state, bus::to_answer(action), e.constraints, e.rules);
  e.hint = step.hint;
  publish_state(key, e, step.update, &step);
  publish_observation(key, e);
}

void EpisodeHost::publish_state(const Key& key, Episode& e, const episode::StateUpdate& u,
                                const episode::EpisodeStep* step) {
  mtg::state_update_t m = bus::to_message(*e.graph, e.state, u);
  if (step != nullptr) {
    m.available = step->outcome.available;
    m.applied = step->outcome.applied;
    m.hint = step->hint;
  }
  m.header = stamp_.next(key.second, e.attempt, "state");
  m.header.run_id = key.first;
  const std::string channel = bus::episode_channel(bus::EpisodeStream::kState, key.second);
  const bool first_attempt = e.attempt == 0;
  if (first_attempt && u.step == faults_.drop_state_step && !u.key.empty()) {
    log::warn("fault injection: dropping the state update of step " + std::to_string(u.step));
    return;
  }
  bus_.publish(channel, m);
  if (first_attempt && u.step == faults_.duplicate_state_step && !u.key.empty()) {
    log::warn("fault injection: duplicating the state update of step " + std::to_string(u.step));
    bus_.publish(channel, m);
  }
}

void EpisodeHost::publish_observation(const Key& key, Episode& e) {
  const graph::SceneGraph& g = *e.graph;
  mtg::observation_t obs{};
  obs.header = stamp_.next(key.second, e.attempt, "observation");
  obs.header.run_id = key.first;
  obs.step = e.state.steps;
  obs.step_limit = e.rules.step_limit;
  obs.done = e.state.phase == episode::Phase::kDone;
  obs.task_text = e.task.text;
  obs.hint = e.hint;
  obs.text = episode::situation_text(g, e.state) + " You have used " + std::to_string(e.state.steps) + " of " +
             std::to_string(e.rules.step_limit) + " steps.";
  if (!obs.done) {
    for (const auto& option : episode::action_space(g, e.state, e.rules)) {
      mtg::action_option_t a{};
      a.key = option.key;
      a.description = option.description;
      obs.actions.push_back(std::move(a));
    }
  }
  obs.n_actions = static_cast<int32_t>(obs.actions.size());
  obs.n_images = 0;
  bus_.publish(bus::episode_channel(bus::EpisodeStream::kObservation, key.second), obs);
  if (obs.done) episodes_.erase(key);  // the judge has what it needs; free the world
}

}  // namespace mtg::services
