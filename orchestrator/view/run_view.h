#pragma once
// One run folder as the viewer serves it: its plan, its results (read again whenever the database
// changes, so a running run shows its progress) and its recordings (indexed in the background).
// Every answer is JSON for the page (docs/view.md).

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "orchestrator/report/compare.h"
#include "orchestrator/report/leaderboard.h"
#include "orchestrator/run/marks.h"
#include "orchestrator/run/provenance.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/view/episode_trace.h"
#include "orchestrator/view/episode_query.h"
#include "orchestrator/view/recording_index.h"

namespace mtg::orchestrator::view {

/// Which episodes a list shows; an unset field matches every episode.
class RunView {
 public:
  /// @throws mtg::Error when `dir` holds no plan.json (not a run folder).
  RunView(std::string name, std::filesystem::path dir);
  ~RunView();
  RunView(const RunView&) = delete;
  RunView& operator=(const RunView&) = delete;

  const std::string& name() const { return name_; }
  const std::filesystem::path& dir() const { return dir_; }

  /// {name, run_id, dir, agents, levels, planned, finished, live}
  nlohmann::json summary();
  /// summary() plus {report (make_report), paper (Table 3), prompt_versions, model_agents}.
  nlohmann::json overview();
  /// make_report over one agent's episodes (the failure section of the overview restricted to
  /// it); null when the run has no episode of that agent.
  nlohmann::json agent_report(const std::string& agent);
  /// People's marks (orchestrator/run/marks.h): {"marks": {"<id>": {flagged, tags, excluded,
  /// reason}}, "trail": [{episode, action, tag, reason, who, at}]}, the trail of one episode only
  /// when `episode` is valid.
  nlohmann::json marks(bus::EpisodeId episode = {}) const;
  /// Stores a person's change. @throws mtg::Error naming the field, or the file when the run's
  /// folder cannot be written.
  void add_mark(const MarkEntry& entry);
  /// {total, offset, rows[...]} of the episodes `query` selects, in its order; each row with
  /// its task's text.
  nlohmann::json episodes(const EpisodeQuery& query, std::size_t offset, std::size_t limit);
  /// Where episode `id` stands in that list: {position (from 0, or null when the list does not
  /// hold it), total, previous, next (episode ids or null)}.
  nlohmann::json neighbours(const EpisodeQuery& query, bus::EpisodeId id);
  /// The episode's result row and its recorded trace (episode_trace), or null if unknown.
  nlohmann::json episode(bus::EpisodeId id, int attempt);
  nlohmann::json truth(bus::EpisodeId id, int attempt);
  std::optional<RecordedImage> image(bus::EpisodeId id, int attempt, int step, int index);
  /// Every recorded image of the attempt (observation_images).
  std::map<std::pair<int, int>, RecordedImage> images(bus::EpisodeId id, int attempt);
  /// What the episode's agent replied, lower case, as the search reads it (RecordingIndex).
  std::string said_of(bus::EpisodeId id) const { return index_.said_of(id); }
  /// For a comparison: the run's name, rows and task set (provenance.h, task_set_identity).
  RunRows compare_rows();
  /// Its rows and suite for a leaderboard (report/leaderboard.h), without excluded episodes.
  LeaderboardRun leaderboard_run();
  /// What the recordings hold of damage (missing, altered or unreadable stretches), once they are
  /// read to their end now: the indexer thread may not have got there yet.
  std::vector<std::string> damage_read_through();
  /// Every results row (episode order).
  std::vector<EpisodeRow> all_rows() { return *rows(); }

 private:
  using Rows = std::shared_ptr<const std::vector<EpisodeRow>>;
  Rows rows();  // re-read when results.sqlite changes; shared, so a request never copies them
  std::vector<RecordedMessage> messages_of(bus::EpisodeId id);
  // Read once, on first use: the task set does not change under a run.
  const TaskTexts& task_texts();
  /// The list's search over what agents replied, from the recording's index.
  SaidSearch said_search() const {
    return [this](bus::EpisodeId id, const std::string& needle) { return index_.said_contains(id, needle); };
  }

  std::string name_;
  std::filesystem::path dir_;
  nlohmann::json plan_summary_;
  std::size_t planned_ = 0;
  std::int64_t per_repeat_ = 0;  // episodes of one repeat (run_plan.h lays them out repeat by repeat)
  std::filesystem::path tasks_db_;

  std::once_flag texts_once_;
  TaskTexts texts_;

  std::mutex rows_mutex_;
  std::string rows_stamp_;  // sizes and times of the database files last read
  Rows rows_ = std::make_shared<const std::vector<EpisodeRow>>();
  Rows overview_rows_;  // the rows overview_ was made from
  std::int64_t overview_marks_ = -1;  // and the marks' version (marks_version)
  nlohmann::json overview_;

  RecordingIndex index_;
  std::atomic<bool> stop_{false};
  std::thread indexer_;  // refreshes the index about once a second
};

/// The runs' names as the viewer shows them: their folders' names, made unique with "-2", "-3"...
std::vector<std::string> run_names(const std::vector<std::filesystem::path>& dirs);

/// The JSON of one results row, as lists and the episode page show it.
nlohmann::json row_json(const EpisodeRow& row);

}  // namespace mtg::orchestrator::view
