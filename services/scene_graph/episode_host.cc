#include "services/scene_graph/episode_host.h"

#include <algorithm>

#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/error_events.h"
#include "bus/process/faults.h"
#include "core/episode/state_delta.h"
#include "core/episode/transcript.h"
#include "core/render/render_pool.h"
#include "core/render/view.h"
#include "core/tasks/lookalike_aid.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/heartbeat_t.hpp"
#include "mtg/observation_t.hpp"
#include "mtg/state_update_t.hpp"

namespace mtg::services {

FaultInjection FaultInjection::from_env() {
  FaultInjection f;
  f.drop_state_step = process::fault_setting("drop_state");
  f.duplicate_state_step = process::fault_setting("dup_state");
  return f;
}

EpisodeHost::EpisodeHost(bus::Bus& bus, bus::HeaderStamper& stamp, graph::SceneCache& scenes, std::string run_id,
                         FaultInjection faults, ImageOptions images)
    : bus_(bus), stamp_(stamp), scenes_(scenes), run_id_(std::move(run_id)), faults_(faults), images_(std::move(images)),
      starts_(bus, run_id_, [this](const mtg::episode_start_t& s, const mtg::episode_truth_t& t) { on_start(s, t); }) {
  bus_.subscribe<mtg::agent_action_t>(bus::episode_channel(bus::EpisodeStream::kAction),
                                      [this](const std::string&, const mtg::agent_action_t& m) {
                                        if (run_id_.empty() || m.header.run_id == run_id_) on_action(m);
                                      });
  bus_.subscribe<mtg::render_result_t>(bus::kRenderResult, [this](const std::string&, const mtg::render_result_t& m) {
    if (run_id_.empty() || m.header.run_id == run_id_) on_render_result(m);
  });
  images_.renderers = std::max(1, images_.renderers);
  renderer_pids_.assign(static_cast<std::size_t>(images_.renderers), 0);
  bus_.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [this](const std::string&, const mtg::heartbeat_t& m) {
    if (!run_id_.empty() && m.header.run_id != run_id_) return;
    if (const auto k = bus::renderer_index(m.role); k && *k < images_.renderers) on_renderer_beat(*k, m.pid);
  });
}

int EpisodeHost::renderer_of(Episode& e) {
  if (e.renderer >= 0) return e.renderer;
  std::vector<int> load(static_cast<std::size_t>(images_.renderers), 0);
  for (const auto& [key, other] : episodes_) {
    if (other.renderer >= 0) ++load[static_cast<std::size_t>(other.renderer)];
  }
  e.renderer = render::least_loaded(load);
  return e.renderer;
}

void EpisodeHost::send_request(Episode& e) {
  bus_.publish(bus::render_request_channel(renderer_of(e)), e.request);
}

void EpisodeHost::on_renderer_beat(int index, int pid) {
  int& known = renderer_pids_[static_cast<std::size_t>(index)];
  const bool replaced = known != 0 && known != pid;
  known = pid;
  if (!replaced) return;
  // What the dead renderer held never comes: ask its successor, once per request. A request that
  // outlives two renderers is not drawn again (it may be what kills them): the episode ends in an
  // error and the orchestrator runs it again.
  std::vector<Key> lost;
  for (auto& [key, e] : episodes_) {
    if (!e.awaiting_images || e.renderer != index) continue;
    if (e.resent_on_restart) {
      lost.push_back(key);
      continue;
    }
    e.resent_on_restart = true;
    e.requested_at = std::chrono::steady_clock::now();
    log::warn("episode " + to_string(key.second) + ": " + bus::renderer_role(index) +
              " was restarted; asking it again for step " + std::to_string(e.request.request_id));
    send_request(e);
  }
  for (const Key& key : lost) {
    Episode& e = *episodes_.find(key);
    report_error(key, e.attempt, "step " + std::to_string(e.request.request_id) + " outlived two renderers (" +
                                     bus::renderer_role(index) + " restarted twice while drawing it)");
    finish_observation(key, e);
  }
}

void EpisodeHost::on_start(const mtg::episode_start_t& start, const mtg::episode_truth_t& truth) {
  if (!episodes_.is_new_attempt(start.header)) return;  // a duplicate or an older attempt
  const Key key = Episodes::key_of(start.header);
  Episode* started = nullptr;
  try {
    Episode e;
    e.task = bus::from_messages(start.task, truth);
    e.graph = &scenes_.get(e.task.scene, start.data_dir);
    e.constraints.protected_objects = episode::task_goal_from_json(*e.graph, e.task.goal).protected_objects();
    e.rules = bus::episode_rules(start);
    e.state = episode::initial_state(*e.graph, e.rules.numbering);
    e.render = start.render;
    e.data_dir = start.data_dir;
    // The first observation tells which look-alikes the text means (and shows them, with images),
    // in the words and images the run's look-alike aid gives.
    tasks::TaskWords words =
        tasks::task_words(e.task.id, e.task.text, e.task.identify, e.rules.lookalike_aid, e.render);
    e.task.text = std::move(words.text);
    e.hint = std::move(words.hint);
    started = &episodes_.start(start.header, std::move(e));
  } catch (const Error& err) {
    report_error(key, start.header.attempt, err.what());
    return;
  }
  Episode& e = *started;
  // Step 0: the initial world for the judge, then the first observation for the agent.
  episode::StateUpdate initial;
  initial.side = -1;
  publish_state(key, e, initial);
  publish_observation(key, e);
}

void EpisodeHost::on_action(const mtg::agent_action_t& action) {
  const Key key = Episodes::key_of(action.header);
  Episode* found = episodes_.current(action.header);
  if (found == nullptr) return;
  Episode& e = *found;
  if (e.awaiting_images && action.step == e.state.steps && e.state.phase != episode::Phase::kDone) {
    // An answer to this step: the renderer's observation reached the agent before its reply
    // reached us, so the observation is out.
    finish_observation(key, e, true);
  }
  if (action.step != e.state.steps || e.state.phase == episode::Phase::kDone || e.awaiting_images) {
    return;  // stale, duplicate or late: never applied twice
  }
  const episode::EpisodeStep step =
      episode::step_episode(*e.graph, e.state, bus::to_answer(action), e.constraints, e.rules);
  e.hint = step.hint;
  if (step.outcome.picked.valid()) e.held_number = std::stoi(step.update.key.substr(1));  // "o<N>"
  if (!e.state.held.valid()) e.held_number = 0;
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
  const std::string channel = bus::episode_channel(bus::EpisodeStream::kState);
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
  obs.text = episode::observation_text(g, e.state, e.rules);
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
  e.words.pack(obs, codec_);
  send_observation(key, e, std::move(obs));
}

void EpisodeHost::send_observation(const Key& key, Episode& e, mtg::observation_t obs) {
  std::vector<render::ViewRequest> views =
      e.render ? render::observation_views(e.state, images_.width, images_.height, e.rules.min_region_size)
               : std::vector<render::ViewRequest>{};
  if (e.render) {
    // The held item numbered as it was picked; the task-provided close-ups of look-alikes with
    // the first observation, and numbered afresh where the robot stands at theirs.
    render::add_close_ups(*e.graph, e.state, e.task.identify, e.held_number, images_.width, images_.height,
                          e.close_ups, views, e.rules.lookalike_aid);
  }
  e.pending = std::move(obs);
  if (views.empty()) {
    finish_observation(key, e);
    return;
  }
  const graph::SceneGraph& g = *e.graph;
  mtg::render_request_t& r = e.request;
  r = mtg::render_request_t{};
  r.header = stamp_.next(key.second, e.attempt, "render");
  r.header.run_id = key.first;
  r.request_id = e.state.steps;
  r.scene = e.task.scene;
  r.data_dir = e.data_dir;
  r.width = images_.width;
  r.height = images_.height;
  r.encoding = images_.encoding;
  r.state = bus::to_message(episode::state_delta(g, e.state));
  r.min_region_size = e.rules.min_region_size;
  for (const render::ViewRequest& v : views) r.views.push_back(bus::to_message(g, v));
  r.n_views = static_cast<int32_t>(r.views.size());
  // The renderer publishes the observation with its images: each image crosses the bus once.
  r.with_observation = true;
  r.observation = e.pending;
  e.awaiting_images = true;
  e.resent = false;
  e.resent_on_restart = false;
  e.requested_at = std::chrono::steady_clock::now();
  send_request(e);
}

void EpisodeHost::finish_observation(const Key& key, Episode& e, bool published) {
  e.awaiting_images = false;
  if (!published) {
    e.pending.n_images = static_cast<int32_t>(e.pending.images.size());
    bus_.publish(bus::episode_channel(bus::EpisodeStream::kObservation), e.pending);
  }
  if (e.pending.done) {
    episodes_.erase(key);  // the judge has what it needs; free the world
    stamp_.forget_episode(key.second);
    return;
  }
  e.pending = mtg::observation_t{};
}

void EpisodeHost::on_render_result(const mtg::render_result_t& result) {
  const Key key = Episodes::key_of(result.header);
  Episode* found = episodes_.current(result.header);
  if (found == nullptr) return;
  Episode& e = *found;
  if (!e.awaiting_images || result.request_id != e.request.request_id) {
    return;  // for another step or attempt, or a second answer to a resent request
  }
  if (!result.ok) {
    report_error(key, e.attempt, "no images for step " + std::to_string(result.request_id) + ": " + result.error);
  }
  // Done right, the renderer published the observation with its images before this reply.
  finish_observation(key, e, result.ok);
}

void EpisodeHost::check_render_timeouts() {
  const auto now = std::chrono::steady_clock::now();
  const auto limit = std::chrono::duration<double>(images_.timeout_s);
  std::vector<Key> expired;
  for (auto& [key, e] : episodes_) {
    if (!e.awaiting_images || now - e.requested_at < limit) continue;
    if (!e.resent) {
      e.resent = true;
      e.requested_at = now;
      // A renderer that does not answer may be gone or stuck: in a pool, the next one is asked,
      // and the episode stays with it.
      const int was = renderer_of(e);
      e.renderer = (was + 1) % images_.renderers;
      log::warn("episode " + to_string(key.second) + ": no answer from " + bus::renderer_role(was) + ", asking " +
                bus::renderer_role(e.renderer));
      send_request(e);
    } else {
      expired.push_back(key);
    }
  }
  for (const Key& key : expired) {
    Episode& e = *episodes_.find(key);
    report_error(key, e.attempt, "no renderer answered for step " + std::to_string(e.request.request_id) +
                                     "; the observation goes without images");
    finish_observation(key, e);
  }
}

void EpisodeHost::report_error(const Key& key, int attempt, const std::string& message) {
  mtg::error_event_t ev =
      bus::error_event(stamp_.sender(), bus::Severity::kFailure, "episode " + to_string(key.second) + ": " + message);
  ev.header = stamp_.next(key.second, attempt, "error");
  ev.header.run_id = key.first;
  bus_.publish(bus::kError, ev);
  log::error(ev.message);
}

}  // namespace mtg::services
