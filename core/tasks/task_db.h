#pragma once
// The task database (one SQLite file per task set; schema in docs/tasks.md) and its JSONL export.
// Writing goes to a temporary file that is renamed at the end, so an interrupted run never
// leaves a half-written database behind.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/tasks/feasibility.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// Writes a task database set by set, so that a job over many scenes need not hold every set:
/// each set's rows go in when it is added, the metadata and votes at finish(), and the file
/// appears (renamed from `<file>.partial`) only then. Without finish() nothing is left behind.
/// With `jsonl` not empty, the same tasks also go there, one per line, keys sorted. Chunks are
/// compressed on up to `jobs` threads; the bytes written do not depend on it.
class TaskDbWriter {
 public:
  TaskDbWriter(const std::filesystem::path& file, const TaskOptions& options, const std::filesystem::path& jsonl = {},
               int jobs = 1);
  ~TaskDbWriter();
  TaskDbWriter(const TaskDbWriter&) = delete;
  TaskDbWriter& operator=(const TaskDbWriter&) = delete;

  /// @throws mtg::Error naming the file.
  void add(const TaskSet& set);
  /// @throws mtg::Error naming the file.
  void finish(const std::vector<Vote>& votes);

 private:
  struct Open;
  std::filesystem::path file_, jsonl_;
  TaskOptions options_;
  int jobs_ = 1;
  std::unique_ptr<Open> open_;
};

/// Writes every task of `sets` (and the Level 4 votes), and with `jsonl` the same tasks one per
/// line, keys sorted. @throws mtg::Error naming the file.
void write_task_db(const std::filesystem::path& file, const std::vector<TaskSet>& sets,
                   const std::vector<Vote>& votes, const TaskOptions& options,
                   const std::filesystem::path& jsonl = {});

/// A task as one JSON object (a JSONL line, an element of a database chunk), and back.
nlohmann::json task_to_json(const Task& task);
/// @throws mtg::Error naming the missing or mistyped field.
Task task_from_json(const nlohmann::json& j);

/// Tasks of the database, optionally only some levels, in id order.
/// @throws mtg::Error if the file is missing or is not a task database.
std::vector<Task> read_tasks(const std::filesystem::path& file, const std::set<int>& levels = {});

/// Per scene, the dataset files its tasks were made from (the `dataset` meta entry).
/// @throws mtg::Error if the file is not a task database.
std::map<std::string, scene::DatasetFingerprint> read_dataset_fingerprints(const std::filesystem::path& file);

/// The generator options the task set was made with (TaskOptions::to_json(), the config_json
/// meta entry); a JSON discarded value when that entry does not parse.
/// @throws mtg::Error if the file is not a task database.
nlohmann::json read_generator_config(const std::filesystem::path& file);

/// Counts per level ("levels": {"1": n, ...}), per type, per scene, total, plus the meta table.
nlohmann::json task_db_stats(const std::filesystem::path& file);

}  // namespace mtg::tasks
