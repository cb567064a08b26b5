#include "services/judge/judge_host.h"

#include <chrono>
#include <cstdint>

#include "bus/channels.h"
#include "bus/process/faults.h"
#include "bus/convert.h"
#include "core/tasks/task.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/judge_event_t.hpp"

namespace mtg::services {

JudgeHost::JudgeHost(bus::Bus& bus, bus::HeaderStamper& stamp, graph::SceneCache& scenes, std::string run_id)
    : bus_(bus), stamp_(stamp), scenes_(scenes), run_id_(std::move(run_id)),
      starts_(bus, run_id_, [this](const mtg::episode_start_t& s, const mtg::episode_truth_t& t) { on_start(s, t); }) {
  auto mine = [this](const mtg::header_t& h) { return run_id_.empty() || h.run_id == run_id_; };
  bus_.subscribe<mtg::state_update_t>(bus::episode_channel(bus::EpisodeStream::kState),
                                      [this, mine](const std::string&, const mtg::state_update_t& m) {
                                        if (mine(m.header)) on_state(m);
                                      });
  bus_.subscribe<mtg::agent_action_t>(bus::episode_channel(bus::EpisodeStream::kAction),
                                      [this, mine](const std::string&, const mtg::agent_action_t& m) {
                                        if (mine(m.header)) on_action(m);
                                      });
}

namespace {

// Test hook (MTG_FAULTS="judge_busy:<ms>", once per MTG_FAULT_MARKS folder): the main thread works
// for that long without returning to its loop, as a judge on a machine at load 13 may, so the hang
// rule's "slow, not hung" can be seen end to end.
void work_without_beating() {
  const int ms = process::fault_setting("judge_busy");
  if (ms <= 0 || !process::first_time_fault("judge_busy")) return;
  log::warn("fault injection: working " + std::to_string(ms) + " ms without a heartbeat");
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  volatile std::uint64_t spins = 0;
  while (std::chrono::steady_clock::now() < until) spins = spins + 1;
}

}  // namespace

void JudgeHost::on_start(const mtg::episode_start_t& start, const mtg::episode_truth_t& truth) {
  work_without_beating();
  const std::vector<mtg::state_update_t> early_states = early_states_.take(start.header);
  const std::vector<mtg::agent_action_t> early_actions = early_actions_.take(start.header);
  if (!episodes_.is_new_attempt(start.header)) return;  // a duplicate or an older attempt
  Episode e;
  e.task_id = start.task.task_id;
  e.agent = start.agent;
  e.level = start.task.level;
  try {
    const bus::EpisodeTask task = bus::from_messages(start.task, truth);
    e.graph = &scenes_.get(task.scene, start.data_dir);
    e.judge = std::make_unique<episode::EpisodeJudge>(*e.graph, episode::task_goal_from_json(*e.graph, task.goal),
                                                      task.level);
  } catch (const Error& err) {
    log::error("episode " + std::to_string(start.header.episode_id) + ": " + err.what());
    return;
  }
  episodes_.start(start.header, std::move(e));
  for (const mtg::agent_action_t& a : early_actions) on_action(a);
  for (const mtg::state_update_t& u : early_states) on_state(u);
}

void JudgeHost::on_action(const mtg::agent_action_t& action) {
  Episode* found = episodes_.current(action.header);
  if (found == nullptr) {
    if (episodes_.is_new_attempt(action.header)) early_actions_.hold(action);
    return;
  }
  Episode& e = *found;
  if (e.actions_seen[action.step]) return;
  e.actions_seen[action.step] = true;
  e.usage.add(bus::answer_usage(action), action.provider != "builtin", action.prompt_version);
  if (!action.error.empty()) e.provider_error = action.error;
}

void JudgeHost::on_state(const mtg::state_update_t& m) {
  Episode* found = episodes_.current(m.header);
  if (found == nullptr) {
    if (episodes_.is_new_attempt(m.header)) early_states_.hold(m);
    return;
  }
  Episode& e = *found;
  if (e.source.empty()) e.source = m.header.sender;
  if (m.header.sender != e.source) return;  // another scene-graph service's copy
  switch (sequence_.observe(m.header)) {
    case bus::SequenceTracker::Verdict::kDuplicate:
      return;
    case bus::SequenceTracker::Verdict::kGap:
      finish(m.header, e, "lost state update(s) before seq " + std::to_string(m.header.seq));
      return;
    case bus::SequenceTracker::Verdict::kInOrder:
      break;
  }
  episode::StateUpdate u;
  try {
    u = bus::from_message(*e.graph, m);
  } catch (const Error& err) {
    finish(m.header, e, err.what());
    return;
  }
  for (const episode::JudgeEvent& ev : e.judge->observe(u)) {
    mtg::judge_event_t out{};
    out.header = stamp_.next(bus::episode_of(m.header), m.header.attempt, "judge");
    out.header.run_id = m.header.run_id;
    out.step = ev.step;
    out.kind = "milestone";
    out.subtask = static_cast<int8_t>(ev.part);
    out.milestone = static_cast<int8_t>(ev.milestone);
    out.ip = ev.ip;
    out.text = ev.text;
    bus_.publish(bus::episode_channel(bus::EpisodeStream::kJudge), out);
  }
  if (e.judge->done()) finish(m.header, e);
}

void JudgeHost::finish(const mtg::header_t& h, Episode& e, const std::string& transport_error) {
  mtg::episode_result_t r{};
  r.header = stamp_.next(bus::episode_of(h), h.attempt, "result");
  r.header.run_id = h.run_id;
  r.task_id = e.task_id;
  r.agent = e.agent;
  r.level = static_cast<int8_t>(e.level);
  if (transport_error.empty()) {
    const episode::Verdict v = e.judge->verdict();
    bus::fill_result(v, r);
    if (v.cause == episode::Cause::kProviderError && !e.provider_error.empty()) r.detail += ": " + e.provider_error;
  } else {
    r.success = false;
    r.stage = episode::to_string(episode::Stage::kStart);
    r.cause = episode::to_string(episode::Cause::kTransportError);
    r.detail = transport_error;
    log::warn("episode " + std::to_string(h.episode_id) + " attempt " + std::to_string(h.attempt) + ": " +
              transport_error + " (to be retried)");
  }
  bus::set_usage(r, e.usage);
  bus_.publish(bus::kEpisodeResult, r);
  sequence_.forget_episode(h.run_id, bus::episode_of(h));
  episodes_.erase(EpisodeTable::key_of(h));
  stamp_.forget_episode(bus::episode_of(h));
}

}  // namespace mtg::services
