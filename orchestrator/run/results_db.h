#pragma once
// results.sqlite of a run: one row per episode, its verdict written once (the first final result
// wins), so resuming, retries and duplicated result messages can never count an episode twice.
// A row of an episode the infrastructure gave up on (status "error", no verdict) is replaced by
// a later attempt's: a resume runs such episodes again.
// Schema in docs/runtime.md.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bus/episode_id.h"
#include "bus/recording_ref.h"
#include "core/episode/usage.h"
#include "core/store/sqlite.h"
#include "mtg/episode_result_t.hpp"

namespace mtg::orchestrator {

struct EpisodeRow {
  bus::EpisodeId episode_id;
  std::string task_id, scene, task_type, agent;
  int level = 0;
  int attempt = 0;
  bool success = false;
  double ip = 0.0;
  std::string stage, cause;
  int steps = 0, invalid_actions = 0;
  episode::EpisodeUsage usage;  // telemetry: what the agent's answers cost
  double wall_ms = 0.0;      // telemetry: wall time of the attempt
  std::string worker;        // telemetry: the worker that ran it (multi-host runs; "" = this machine)
  std::string subtask_ip;    // JSON list
  std::string detail;
  std::string status = "scored";  // "scored", or "error" (infrastructure gave up; excluded from SR/IP)
};

/// Copies the verdict of a judge's result into `row` (success, IP, stage, cause, steps, invalid
/// actions, sub-task IP, detail); identity, usage and timing stay as they are.
void set_verdict(EpisodeRow& row, const mtg::episode_result_t& result);

class ResultsDb {
 public:
  /// Opens (creating if needed) `file`.
  explicit ResultsDb(const std::filesystem::path& file);
  /// Checkpoints and leaves the file in rollback-journal mode (no -wal/-shm files behind).
  ~ResultsDb();
  /// Inserts unless the episode already has a row with a verdict (one given up is replaced);
  /// returns whether it wrote. With `recording`, where the attempt's recording is kept is stored
  /// in the same transaction (table `recordings`, bus/recording_ref.h), only if the row is.
  bool insert(const EpisodeRow& row, const bus::RecordingRef* recording = nullptr);
  std::vector<EpisodeRow> rows() const;
  const std::filesystem::path& file() const { return file_; }

 private:
  bool insert_row(const EpisodeRow& row);

  std::filesystem::path file_;
  std::unique_ptr<store::Database> db_;
  std::unique_ptr<store::Statement> insert_;  // prepared once: parsing it per row was a tenth of a run's orchestrator
};

/// Rows of an existing results file (read-only). @throws mtg::Error if it is missing.
std::vector<EpisodeRow> read_results(const std::filesystem::path& file);

/// The columns that judge results must reproduce exactly (no wall-clock telemetry).
std::string verdict_fingerprint(const EpisodeRow& row);

}  // namespace mtg::orchestrator
