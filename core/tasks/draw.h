#pragma once
// Drawing a sample of tasks (docs/tasks.md, "Drawing a sample"). A uniform draw follows the set's
// own shape, and that shape is lopsided: one platform with many items and many destinations (a
// kitchen counter) makes half of Level 2, so a 100-task sample is half counter. A stratified draw
// deals tasks round-robin over groups that say where a task happens, so every platform and kind
// of task gets its turn before any gets a second one.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/tasks/task.h"

namespace mtg::tasks {

enum class DrawKind {
  kStratified,  ///< round-robin over strata (stratum_of), then over sub-strata, seeded
  kUniform,     ///< a seeded draw without replacement from the whole group
};
/// "stratified" or "uniform". @throws mtg::Error otherwise.
DrawKind draw_kind_from_string(const std::string& name);
const char* to_string(DrawKind kind);

/// Where a task happens, for the stratified draw: the stratum dealt first and the sub-stratum
/// within it. Levels 1-2: the source platform, then the item's model (its name without the
/// instance index). Level 3: its first part's source platform, then every other platform its parts
/// touch. Level 4: the outcome kind, then the template.
struct Stratum {
  std::string primary;
  std::string secondary;
};
Stratum stratum_of(const Task& task);
/// What the primary stratum of a level is called in reports ("source platform", "outcome kind").
const char* stratum_name(int level);

/// The seed of the draw of one (scene, level) from a run's or a suite's seed: `mtg run --limit N
/// --seed K` and `mtg suite make --per-level N --seed K` on one task set draw the same tasks.
std::uint64_t draw_seed(std::uint64_t seed, const std::string& scene, int level);

/// Up to `n` tasks of `group` (tasks of one scene and level), drawn with `seed`, in id order; all
/// of them, in id order, when `n` <= 0 or the group is not larger.
std::vector<const Task*> draw_tasks(std::vector<const Task*> group, int n, DrawKind kind, std::uint64_t seed);

/// How spread a sample is on one level: the scene whose biggest primary stratum holds the largest
/// share of that scene's tasks at the level, that stratum ("apt_0/kitchen_counter_1_platform_1")
/// and its share.
struct LevelSpread {
  int level = 0;
  std::int64_t tasks = 0;        ///< of that scene at this level
  std::int64_t strata = 0;       ///< primary strata present in that scene
  std::string biggest;           ///< "<scene>/<stratum>" with most tasks (first by name on a tie)
  std::int64_t biggest_tasks = 0;
  double biggest_share() const { return tasks > 0 ? static_cast<double>(biggest_tasks) / static_cast<double>(tasks) : 0.0; }
};
/// Per level, the most lopsided scene's figures.
std::map<int, LevelSpread> spread_of(const std::vector<const Task*>& tasks);
/// {"<level>": {"stratum", "tasks", "strata", "biggest", "biggest_tasks", "biggest_share"}}
nlohmann::json to_json(const std::map<int, LevelSpread>& spread);

}  // namespace mtg::tasks
