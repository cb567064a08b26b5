#pragma once
// Result rows made by hand for the statistics tests (compare, leaderboard), where every figure
// can be worked out on paper.

#include <cstdint>
#include <string>

#include "orchestrator/run/results_db.h"

namespace mtg::testing {

/// A scored episode of `agent` on `task`: IP 100 on success, else `ip`, failed at the start by
/// navigation.
inline orchestrator::EpisodeRow scored_row(std::uint32_t episode, const std::string& task, const std::string& agent,
                                           int level, bool success, double ip = 0.0) {
  orchestrator::EpisodeRow r;
  r.episode_id = bus::EpisodeId(episode);
  r.task_id = task;
  r.agent = agent;
  r.level = level;
  r.success = success;
  r.ip = success ? 100.0 : ip;
  r.stage = success ? "done" : "start";
  r.cause = success ? "" : "navigation";
  return r;
}

}  // namespace mtg::testing
