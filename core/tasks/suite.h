#pragma once
// A suite: a frozen, self-contained sample of tasks that others can run and cite (docs/suites.md).
// One JSON file holds the tasks themselves, the dataset files each scene was made from, the
// generator's options, how the sample was drawn, and a SHA-256 digest over all of that, which is
// the suite's identity ("NAME@<first 12 digits>"). A suite needs no task set at hand: a later
// generator that words or numbers tasks differently leaves a suite's tasks as they were, so a
// figure measured on it stays comparable with any other measured on it.
//
// File: {"format": "mtg-suite/1", "id", "digest", "made_with": {mtg_version, git_revision},
// "content": {name, license, generator, draw, spread, dataset, tasks}}; the digest is the SHA-256
// of content's compact JSON (keys sorted). `made_with` says which build drew it and is outside the
// digest: two builds drawing the same tasks from the same set make the same suite.

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/scene/dataset_fingerprint.h"
#include "core/tasks/draw.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

inline constexpr const char* kSuiteFormat = "mtg-suite/1";
/// The largest suite file read (the standard suite of 1,200 tasks is 1.2 MiB): a larger one is
/// refused before it is read, not parsed into memory.
inline constexpr std::uintmax_t kMaxSuiteBytes = std::uintmax_t{256} << 20;
/// The terms of data derived from ReplicaCAD (its NOTICE.md): a suite carries them.
inline constexpr const char* kReplicaCadLicense =
    "CC BY-NC 4.0: the tasks are derived from ReplicaCAD (Szot et al., Habitat 2.0, NeurIPS 2021) and carry its "
    "terms: attribution required, no commercial use (https://creativecommons.org/licenses/by-nc/4.0/)";

/// How the sample was drawn.
struct SuiteDraw {
  int per_level = 0;             ///< tasks per (scene, level), at most
  std::uint64_t seed = 0;
  DrawKind kind = DrawKind::kStratified;
  std::set<int> levels;
  std::set<std::string> scenes;
  nlohmann::json sizing;         ///< how per_level was chosen from power (null when given)
};

struct Suite {
  std::string name;
  std::string license = kReplicaCadLicense;
  /// {"task_format": kGeneratorVersion of the set, "config_hash", "config", "seed"}: the generator
  /// and options that made the tasks.
  nlohmann::json generator;
  SuiteDraw draw;
  std::map<std::string, scene::DatasetFingerprint> dataset;  ///< of the scenes its tasks are in
  std::vector<Task> tasks;                                   ///< in id order
  /// Set by read_suite / finish_suite: what identifies it.
  std::string digest;
  /// The build that drew it (outside the digest).
  nlohmann::json made_with;

  /// "NAME@<first 12 hex digits of the digest>".
  std::string id() const;
};

/// Draws a suite from a task set's tasks: in each (scene, level) of `draw` (every scene of the set
/// when draw.scenes is empty), draw.per_level tasks by draw.kind, seeded by draw_seed(draw.seed,
/// scene, level). `dataset` and `generator` come from the task set. @throws mtg::Error when no
/// task matches, or a scene asked for has none.
Suite draw_suite(std::string name, const std::vector<Task>& tasks, SuiteDraw draw, nlohmann::json generator,
                 const std::map<std::string, scene::DatasetFingerprint>& dataset);

/// How spread its tasks are (spread_of, as JSON): content's "spread".
nlohmann::json suite_spread(const Suite& suite);

/// The part the digest covers, as JSON (keys sorted when dumped).
nlohmann::json suite_content(const Suite& suite);
/// SHA-256 of suite_content(suite).dump().
std::string suite_digest(const Suite& suite);

/// Fills the digest (and the build in made_with) and writes the file atomically, one task a line.
/// @throws mtg::Error naming the file when it cannot be written, or `name` when it is not a plain
/// name (letters, digits, '.', '_', '-').
void write_suite(const std::filesystem::path& file, Suite& suite);

/// Reads and checks a suite: a file that is not JSON or is cut short, a format other than
/// kSuiteFormat, a digest that does not match the content (an edit), an id that does not match
/// the digest, a malformed task. @throws mtg::Error, one line naming the file and what is wrong.
Suite read_suite(const std::filesystem::path& file);

/// Whether the file is a suite rather than a task database (its first byte opens a JSON object),
/// so every reader of a task set takes either. False for a file that cannot be read.
bool is_suite_file(const std::filesystem::path& file);

/// The suite's answer to a task database's meta key ("format", "config_hash", "config_json",
/// "generator_version", "seed", "scenes", "dataset", "suite_id"), or nullopt.
std::optional<std::string> suite_meta(const Suite& suite, const std::string& key);

}  // namespace mtg::tasks
