#pragma once
// Re-scoring a run from its recording alone: the episode starts and the agents' answers are read
// back from the run's LCM logs, replayed through the episode rules and judged again in-process
// (no agent, no bus). After a judge fix this shows exactly which verdicts change.

#include <filesystem>
#include <string>
#include <vector>

#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {

struct RejudgeReport {
  std::vector<EpisodeRow> rows;       // re-scored rows (same episodes as results.sqlite)
  std::int64_t identical = 0;
  std::vector<std::string> differences;  // one line per changed episode
  std::vector<std::string> damage;       // one line per unreadable stretch of the recording (bus::describe)
  /// One line per stored episode that could not be judged again: the recording lacks its start or
  /// an answer (with the damage that explains it, when there is some). Not in `rows`.
  std::vector<std::string> unjudged;
};

/// @throws mtg::Error if the run folder, its plan, results or recording are missing.
RejudgeReport rejudge_run(const std::filesystem::path& run_dir);

}  // namespace mtg::orchestrator
