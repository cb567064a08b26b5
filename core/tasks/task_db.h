#pragma once
// The task database (one SQLite file per task set; schema in docs/tasks.md) and its JSONL export.
// Writing goes to a temporary file that is renamed at the end, so an interrupted run never
// leaves a half-written database behind.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/tasks/feasibility.h"
#include "core/tasks/task.h"
#include "core/util/atomic_file.h"

namespace mtg::tasks {

/// Tasks made into the database's chunks (64 to a chunk, compressed) and not yet stored.
struct TaskChunk {
  struct Row {
    std::string id, scene, type;
    int level = 0;
  };
  std::size_t size = 0;            // of the chunk's JSON text
  std::string body;                // what is stored: zlib, or the text when that is not smaller
  std::vector<Row> rows;           // its tasks, in slot order
  std::vector<std::size_t> line_sizes;  // each task's JSON in the text: a JSONL export cuts it
                                       // from the stored text rather than keeping a copy
};

/// Writes a task database scene by scene, so that a job over many scenes need not hold every
/// set, nor even one whole set. A scene's tasks are made into chunks as they come (make_chunks,
/// which any thread may call for its own scene) and stored in order (store); end_scene() then
/// records what was dropped and the files the scene came from; the metadata and votes go in at
/// finish(), and the file appears (renamed from this writer's own partial file, atomic_file.h) only then. Without finish()
/// nothing is left behind. A scene's chunks are counted from its first task, and only its last
/// chunk may be short, so the bytes depend only on the tasks and their order: not on how they
/// were batched, nor on `jobs`, the threads each call compresses on. With `jsonl` not empty, the
/// same tasks also go there, one per line, keys sorted.
class TaskDbWriter {
 public:
  TaskDbWriter(const std::filesystem::path& file, const TaskOptions& options, const std::filesystem::path& jsonl = {},
               int jobs = 1);
  ~TaskDbWriter();
  TaskDbWriter(const TaskDbWriter&) = delete;
  TaskDbWriter& operator=(const TaskDbWriter&) = delete;

  /// The whole chunks at the front of `tasks` (a scene's next tasks, in order; with `last`, the
  /// short chunk at the end too), taken out of it. Touches nothing of the writer: threads may
  /// make their own scenes' chunks at once. @throws mtg::Error naming the file.
  std::vector<TaskChunk> make_chunks(std::vector<Task>& tasks, bool last) const;
  /// Stores chunks as the next of the current scene. @throws mtg::Error naming the file.
  void store(std::vector<TaskChunk> chunks);
  /// Ends the current scene (its chunks stored): what was dropped, the files it came from.
  void end_scene(const TaskSet& set);
  /// A whole scene at once: its tasks, then end_scene(set).
  void add(const TaskSet& set);
  /// @throws mtg::Error naming the file.
  void finish(const std::vector<Vote>& votes);

 private:
  struct Open;
  std::filesystem::path file_, jsonl_;
  TaskOptions options_;
  int jobs_ = 1;
  PartialFile db_partial_;  // before open_: the database closes before its file is moved or removed
  std::optional<PartialFile> jsonl_partial_;
  std::unique_ptr<Open> open_;
  bool scene_open_ = false;  // chunks stored since the last end_scene()
};

/// Writes every task of `sets` (and the Level 4 votes), and with `jsonl` the same tasks one per
/// line, keys sorted. @throws mtg::Error naming the file.
void write_task_db(const std::filesystem::path& file, const std::vector<TaskSet>& sets,
                   const std::vector<Vote>& votes, const TaskOptions& options,
                   const std::filesystem::path& jsonl = {});

/// A task as one JSON object (a JSONL line, an element of a database chunk), and back.
nlohmann::json task_to_json(const Task& task);
/// Appends task_to_json(task).dump() to `out`, written straight from the task (what a database's
/// chunks and the JSONL hold).
void append_task_json(std::string& out, const Task& task);

/// The most steps a stored task may allow, and the longest text it may have (bytes).
inline constexpr int kMaxStepLimit = 1000;
inline constexpr std::size_t kMaxTaskText = 16384;

/// @throws mtg::Error naming the task for a missing or mistyped field, a level other than 1-4, a
/// step limit beyond kMaxStepLimit or a text longer than kMaxTaskText.
Task task_from_json(const nlohmann::json& j);

/// Tasks of the database, optionally only some levels, in id order.
/// @throws mtg::Error if the file is missing or is not a task database.
std::vector<Task> read_tasks(const std::filesystem::path& file, const std::set<int>& levels = {});

/// Each task of the database (optionally only some levels) in storage order, one at a time: a
/// whole set is never held. @throws mtg::Error as read_tasks.
void for_each_task(const std::filesystem::path& file, const std::set<int>& levels, const std::function<void(Task)>& take);

/// Per scene, the dataset files its tasks were made from (the `dataset` meta entry).
/// @throws mtg::Error if the file is not a task database.
std::map<std::string, scene::DatasetFingerprint> read_dataset_fingerprints(const std::filesystem::path& file);

/// One entry of the task set's meta table ("config_hash", "format", ...), or nullopt.
/// @throws mtg::Error if the file is not a task database.
std::optional<std::string> read_task_set_meta(const std::filesystem::path& file, const std::string& key);

/// The generator options the task set was made with (TaskOptions::to_json(), the config_json
/// meta entry); a JSON discarded value when that entry does not parse.
/// @throws mtg::Error if the file is not a task database.
nlohmann::json read_generator_config(const std::filesystem::path& file);

/// Counts per level ("levels": {"1": n, ...}), per type, per scene, total, plus the meta table.
nlohmann::json task_db_stats(const std::filesystem::path& file);

}  // namespace mtg::tasks
