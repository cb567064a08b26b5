#pragma once
// A generated task and the options of the generator (DESIGN.md §3 "Tasks").

#include <cstdint>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/graph/options.h"
#include "core/render/visibility_options.h"
#include "core/scene/dataset_fingerprint.h"
#include "core/tasks/reference.h"

namespace mtg::tasks {

/// mtg-tasks/2: no goal holds before its step, references for look-alikes, stacks against
/// clearance, robust placements, Level 4 objects named unambiguously (docs/tasks.md).
/// mtg-tasks/3: Level 4 of 31 outcome kinds, with the predicates count_on, apart, all_near and
/// none_near, every required object on a platform the text names, no kind above a fifth.
/// mtg-tasks/4: an item keeps its number for the whole episode (episode::Numbering::kStable): the
/// oracle keys of a later step count that way.
/// mtg-tasks/5: platforms as a person uses them (graph::PlatformRules::kReachedAndSeen): a
/// platform inside its furniture is the part an arm reaches through the opening (a TV stand's
/// floor ends at its closed doors), an empty chair is seen from its seat's side.
inline constexpr const char* kGeneratorVersion = "mtg-tasks/5";

/// How items are numbered in runs of tasks of generator format `format` (kGeneratorVersion of
/// the set that made them): stable from mtg-tasks/4 on; the release's per-state numbering for
/// older tasks (their later oracle keys count that way) and for a set that does not say.
episode::Numbering numbering_of_format(const std::string& format);
/// How runs of tasks of format `format` read platforms: as a person uses them from mtg-tasks/5
/// on; as the release for older tasks (their goals, cells and texts were planned on whole
/// surfaces and those arrival sides) and for a set that does not say.
graph::PlatformRules platform_rules_of_format(const std::string& format);

/// How a task's text picks out an object that has look-alikes (referring.h). The scene-graph
/// service shows each such object in a close-up at the first observation; tests resolve the
/// reference against the scene. Names the instance: ground truth, never sent to agents.
struct Identification {
  int part = 0;              // Level 3 sub-task (0 otherwise)
  std::string role;          // "item", "anchor", "anchor2", or "object" (Level 4)
  std::string object;        // the instance meant
  std::string platform;      // the furniture platform the reference is read on
  Reference reference;
  std::string phrase;        // the words in the text, e.g. "the leftmost book"
};
nlohmann::json to_json(const Identification& id);
/// @throws mtg::Error naming the missing field.
Identification identification_from_json(const nlohmann::json& j);
/// A task's identifications as one JSON array (its identify_json), and back.
nlohmann::json to_json(const std::vector<Identification>& ids);
std::vector<Identification> identifications_from_json(const nlohmann::json& j);

/// Where an oracle plan puts one item (world frame, metres), so a checker can verify it.
struct OraclePlacement {
  int part = 0;             // Level 3 sub-task (0 otherwise)
  std::string object;
  std::string platform;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // of the object frame, after placing
  double margin = 0.0;      // m the footprint centre may move and the goal still hold
};
nlohmann::json to_json(const OraclePlacement& p);
/// @throws mtg::Error naming the missing field.
OraclePlacement oracle_placement_from_json(const nlohmann::json& j);
/// A task's placements as one JSON array (its placements_json), and back.
nlohmann::json to_json(const std::vector<OraclePlacement>& placements);
std::vector<OraclePlacement> oracle_placements_from_json(const nlohmann::json& j);

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
  std::vector<Identification> identify;  // objects with look-alikes and how the text names them
  std::vector<OraclePlacement> placements;  // where the oracle plan puts each atomic part's item
};

enum class Ambiguity {
  kNameWithoutId,  // same template name (e.g. two "cup 01") on the platform
  kCategory,       // same semantic class of the dataset (e.g. a sponge dish is a "kitchen utensil")
  kNoun,           // same noun of the scene profile, what a person calls it ("sponge dish"); the
                   // class where the profile has none
};
/// "name", "category" or "noun". @throws mtg::Error otherwise.
Ambiguity ambiguity_from_string(const std::string& name);
const char* to_string(Ambiguity a);

struct TaskOptions {
  std::set<int> levels = {1, 2, 3, 4};
  std::uint64_t seed = 0;
  Ambiguity ambiguity = Ambiguity::kNoun;  // pairs with the paper's nameless action space (docs/tasks.md)
  int level3_count = 10000;     // per scene (the paper's figure)
  int level3_chain = 2;         // sub-tasks per Level 3 task
  int level4_max_moves = 3;     // objects an outcome task may require to move
  double level4_max_kind_share = 0.2;  // no outcome kind above this share of Level 4 (1: no cap)
  double min_margin = 0.005;    // m the oracle's placement lies inside its goal, at least
  double min_goal_area = 4e-4;  // m² of positions for the item's centre that meet the goal and fit
  std::string level4_templates = "builtin";  // or a path to a template JSON file
  episode::RuleOptions rules;
  episode::GoalOptions goals;
  /// What a task may name and count must be clearly visible in the arrival view (docs/tasks.md,
  /// "Seen, not only there"); nullopt: the geometry alone decides (scenes without meshes).
  std::optional<render::VisibilityOptions> visibility = render::VisibilityOptions{};

  /// Canonical JSON (hashed into config_hash; stored in the database).
  nlohmann::json to_json() const;
  /// Hex digest of to_json().dump().
  std::string config_hash() const;
};

/// Candidate tasks the generator did not keep, per reason and level (stored with the task set,
/// printed by `mtg tasks stats`). Reasons: "trivial" (the goal already holds when its step
/// starts), "fragile" (the oracle's placement is less than the margin inside its goal),
/// "small_area" (less than the minimum feasible area for the item's centre), "stack" (the item
/// with what rests on it is taller than the destination's clearance, though the item alone is
/// not), "unidentifiable" (look-alikes no reference tells apart), "vague" (Level 4: the text's
/// words match other objects than the goal's), "unworded" (a direction no key offers in those
/// words: only another object's free space reaches there).
struct DropCounts {
  std::map<std::string, std::map<int, long>> by_reason;
  void add(const std::string& reason, int level, long n = 1) { by_reason[reason][level] += n; }
  void merge(const DropCounts& other);
  /// {"<reason>": {"<level>": n}}
  nlohmann::json to_json() const;
};

/// Tasks of one scene, per level in generation order.
struct TaskSet {
  std::string scene;
  std::vector<Task> tasks;
  std::vector<std::string> warnings;
  DropCounts dropped;
  nlohmann::json coverage = nlohmann::json::array();  // coverage.h: the scene's pickable items
  scene::DatasetFingerprint dataset;  // the files the scene was loaded from
};

}  // namespace mtg::tasks
