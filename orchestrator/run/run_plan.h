#pragma once
// A run's plan: which tasks, which agents, which seeds, how many at once, and the episodes that
// follow from them. Saved as plan.json in the run folder; a second `mtg run` on the same folder
// reads it back and resumes instead of planning anew.

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "bus/episode_id.h"
#include "core/tasks/draw.h"
#include "core/tasks/task.h"

namespace mtg::orchestrator {

struct PlannedEpisode {
  bus::EpisodeId id;
  std::string task_id;
  std::string agent;
  std::uint64_t seed = 0;  // derive_seed(run seed, id)
};

struct RunPlan {
  std::string run_id;            // unique: the folder's name and a random suffix (new_run_id)
  std::string tasks_db;          // absolute path of the task database
  std::vector<std::string> agents;
  std::set<std::string> scenes;  // empty = every scene of the task set
  std::set<int> levels = {1, 2, 3};
  int limit = 0;                 // tasks per (scene, level), drawn with the seed; 0 = all
  tasks::DrawKind draw = tasks::DrawKind::kStratified;  // how `limit` tasks are drawn (tasks/draw.h)
  int repeat = 1;                // episodes per (task, agent), each with its own episode seed
  std::uint64_t seed = 0;
  int parallel = 4;              // attempts in flight; 0 = no cap (remote: the workers' capacities)
  int step_limit = 15;           // at least; a task may ask for more (long L3/L4 plans)
  bool render = false;           // observations carry images (a renderer process runs)
  bool object_names = false;     // the action space and situation text name objects (text-only agents)
  episode::LookalikeAid lookalike_aid = episode::LookalikeAid::kBoth;  // words, close-ups or both
  /// How items are numbered over an episode: as the tasks were planned (tasks::numbering_of_format).
  episode::Numbering numbering = episode::Numbering::kStable;
  /// How the graphs read platforms (reach, empty platforms' arrival sides): as the tasks were
  /// planned (tasks::platform_rules_of_format).
  graph::PlatformRules platform_rules = graph::PlatformRules::kReachedAndSeen;
  int image_width = 640;
  int image_height = 480;
  std::string image_encoding = "png";
  int max_attempts = 3;          // per episode, for infrastructure failures only
  double episode_timeout_s = 60; // without any message about an episode
  std::string data_dir;
  std::string profile = "replica_cad";
  std::string bus_url;
  /// Episodes run on workers (`mtg worker`) of the bus by lease, not on this machine.
  bool remote = false;
  /// With remote: where each attempt's recording goes (remote::RecordingsPlace by name:
  /// "coordinator", "shared:<folder>", "worker").
  std::string recordings = "coordinator";
  /// Run even where the dataset differs from the one the task set was made from.
  bool allow_data_mismatch = false;
  std::vector<PlannedEpisode> episodes;
  /// What made the run (provenance.h), written when it was planned; null in plans from before.
  nlohmann::json provenance;

  nlohmann::json to_json() const;
  /// @throws mtg::Error naming the field.
  static RunPlan from_json(const nlohmann::json& j, const std::string& origin);
};

/// A run's identity: `name` (its folder's name) and 8 random hex digits, so two runs in folders
/// of the same name, or one run after another in the same place, never share an id.
std::string new_run_id(const std::string& name);

/// Draws the tasks and lays out the episodes: tasks in id order, each run by every agent in
/// turn (so agents interleave when episodes run in parallel).
RunPlan make_plan(RunPlan base, const std::map<std::string, tasks::Task>& all_tasks);

/// plan.json in `run_dir`. @throws mtg::Error on a malformed file.
void save_plan(const RunPlan& plan, const std::filesystem::path& run_dir);
RunPlan load_plan(const std::filesystem::path& run_dir);

}  // namespace mtg::orchestrator
