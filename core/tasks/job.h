#pragma once
// One task-generation job, from scene names to a written database: what `mtg tasks` and the
// task-generator service both run.

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/tasks/feasibility.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// Where one scene of a job stands, for a progress line on a terminal.
struct SceneProgress {
  enum class Phase { kLoading, kGraph, kTasks, kDone };
  std::size_t index = 0;     // in GenerationJob::scenes
  Phase phase = Phase::kLoading;
  std::int64_t tasks = 0;    // made so far
};
/// Told when a scene starts loading, building its graph, generating, as its tasks come (in
/// batches) and when it is done. From the generating threads, one call at a time: keep it short.
using SceneProgressFn = std::function<void(const SceneProgress&)>;

struct GenerationJob {
  std::vector<std::string> scenes;
  std::string data_dir;        // "" = default search order
  std::string profile = "replica_cad";
  std::string out;             // SQLite database (required)
  std::string jsonl;           // optional export
  TaskOptions options;
  std::vector<Vote> votes;     // recorded Level 4 votes
  std::vector<VoteBatch> voters;  // live Level 4 voters (model adapters)
  int jobs = 1;                // threads; the output is the same for any number
  SceneProgressFn on_progress; // optional; changes nothing that is written
};

struct SceneReport;
/// Told of each scene once it and every scene before it are generated (a long job is not
/// silent), in scene order. Called from a generating thread, under a lock: keep it short.
using SceneDone = std::function<void(const SceneReport&)>;

struct SceneReport {
  std::string scene;
  std::array<std::int64_t, 4> levels{};  // tasks of level 1..4
  std::int64_t total = 0;
  double seconds = 0.0;                  // telemetry
};

struct GenerationReport {
  std::vector<SceneReport> scenes;
  std::array<std::int64_t, 4> levels{};
  std::int64_t total = 0;
  std::vector<std::string> warnings;     // "<scene>: <warning>"
  double seconds = 0.0;
};

/// Loads each scene, builds its graph, generates, and writes the database (and JSONL) only when
/// everything succeeded. @throws mtg::Error (nothing is written then).
GenerationReport run_generation(const GenerationJob& job, const SceneDone& on_scene = {});

/// Applies generator overrides from JSON (keys: levels, seed, ambiguity, l3_count, l3_chain,
/// l4_max_moves, l4_templates, step_limit, profile). @throws mtg::Error naming an unknown key.
void apply_overrides(GenerationJob& job, const nlohmann::json& overrides);

}  // namespace mtg::tasks
