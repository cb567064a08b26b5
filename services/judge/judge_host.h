#pragma once
// The judge service's episodes: from the bus alone (episode starts and truths, state updates,
// agent actions) it follows each episode with core's EpisodeJudge, publishes milestones as they happen
// and the episode result at the end. A lost state update (a gap in the scene-graph service's
// sequence numbers) cannot be scored: the judge reports cause "transport_error" so the
// orchestrator retries the episode; duplicates are ignored.

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "bus/bus.h"
#include "bus/early_messages.h"
#include "bus/episode_join.h"
#include "bus/episode_table.h"
#include "bus/header.h"
#include "core/episode/judge.h"
#include "core/episode/usage.h"
#include "core/graph/scene_cache.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/state_update_t.hpp"

namespace mtg::services {

class JudgeHost {
 public:
  /// Subscribes to episode starts and truths, state updates and agent actions of run `run_id`
  /// ("" = every run).
  JudgeHost(bus::Bus& bus, bus::HeaderStamper& stamp, graph::SceneCache& scenes, std::string run_id);

  void on_start(const mtg::episode_start_t& start, const mtg::episode_truth_t& truth);
  void on_state(const mtg::state_update_t& update);
  void on_action(const mtg::agent_action_t& action);
  int in_flight() const { return static_cast<int>(episodes_.size()); }

 private:
  struct Episode {
    int attempt = 0;  // set by the table
    std::string task_id;
    std::string agent;
    int level = 0;
    const graph::SceneGraph* graph = nullptr;
    std::unique_ptr<episode::EpisodeJudge> judge;
    std::string source;          // the scene-graph service's sender id (first update)
    episode::EpisodeUsage usage;  // what the answers cost (telemetry; never in the verdict)
    std::string provider_error;  // the agent's last provider error, for the verdict's detail
    std::map<int, bool> actions_seen;  // step -> counted (duplicates of agent actions ignored)
  };
  using EpisodeTable = bus::EpisodeTable<Episode>;

  /// Publishes the verdict of the episode whose message `h` ended it, and forgets it.
  void finish(const mtg::header_t& h, Episode& e, const std::string& transport_error = "");

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  graph::SceneCache& scenes_;
  std::string run_id_;
  EpisodeTable episodes_;
  bus::SequenceTracker sequence_;  // state updates per (run, sender, episode, attempt)
  // What came before its episode's start (bus/early_messages.h).
  bus::EarlyMessages<mtg::state_update_t> early_states_{256};
  bus::EarlyMessages<mtg::agent_action_t> early_actions_{256};
  bus::EpisodeJoin starts_;
};

}  // namespace mtg::services
