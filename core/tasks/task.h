#pragma once
// A generated task and the options of the generator (DESIGN.md §3 "Tasks").

#include <cstdint>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/episode/goals.h"
#include "core/episode/rules.h"

namespace mtg::tasks {

inline constexpr const char* kGeneratorVersion = "mtg-tasks/1";

/// One task as stored (docs/tasks.md). Names, not indices: a task outlives the graph object.
struct Task {
  std::string id;            // "<scene>/L<level>/<6-digit index>"
  std::string scene;
  int level = 1;             // 1..4
  std::string type;          // surface, surface_part, around, direction, between, sequence, outcome
  std::string text;          // the instruction
  std::string item;          // moved item (L1/L2; first sub-task's for L3; "" for L4)
  std::string source;        // its source platform
  std::string destination;   // destination platform
  std::vector<std::string> anchors;
  std::string direction;     // named direction ("" if none)
  nlohmann::json goal;       // structured goal: {"atomic": {...}} / {"sequence": [...]} / {"outcome": {...}}
  std::vector<std::string> oracle;  // action keys that solve it from the initial state
  int step_limit = 15;
  std::string template_id;   // L4
};

enum class Ambiguity {
  kNameWithoutId,  // same template name (e.g. two "cup 01") on the platform
  kCategory,       // same semantic class (e.g. two cups of any model)
};
/// "name" or "category". @throws mtg::Error otherwise.
Ambiguity ambiguity_from_string(const std::string& name);
const char* to_string(Ambiguity a);

struct TaskOptions {
  std::set<int> levels = {1, 2, 3, 4};
  std::uint64_t seed = 0;
  Ambiguity ambiguity = Ambiguity::kNameWithoutId;
  int level3_count = 10000;     // per scene (the paper's figure)
  int level3_chain = 2;         // sub-tasks per Level 3 task
  int level4_max_moves = 3;     // objects an outcome task may require to move
  std::string level4_templates = "builtin";  // or a path to a template JSON file
  episode::RuleOptions rules;
  episode::GoalOptions goals;

  /// Canonical JSON (hashed into config_hash; stored in the database).
  nlohmann::json to_json() const;
  /// Hex digest of to_json().dump().
  std::string config_hash() const;
};

/// Tasks of one scene, per level in generation order.
struct TaskSet {
  std::string scene;
  std::vector<Task> tasks;
  std::vector<std::string> warnings;
};

}  // namespace mtg::tasks
