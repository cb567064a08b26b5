#pragma once
// How much of a scene a task set uses (docs/tasks.md, "Breadth"): the pickable items on
// navigable platforms, which of them the arrival views show and which have look-alikes there
// (recorded with the set when it is made), against the items, source platforms, nouns and
// phrases its tasks use (counted by `mtg tasks stats`).

#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/render/visibility.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// A pickable item on a navigable platform, as the scene stands before any task.
struct CoverageItem {
  std::string object;
  std::string platform;  // the furniture platform it stands on (at any depth)
  std::string noun;      // under the set's ambiguity rule
  bool seen = false;       // clearly visible in that platform's arrival view (always, without visibility rules)
  bool lookalike = false;  // another object there has its noun
};

/// Every pickable item on a navigable platform of `s`, in label and o-order.
std::vector<CoverageItem> coverage_items(const graph::SceneGraph& g, const episode::WorldState& s, Ambiguity rule,
                                         const render::VisibilityOracle* seeing);

nlohmann::json to_json(const std::vector<CoverageItem>& items);
/// @throws mtg::Error naming the field.
std::vector<CoverageItem> coverage_items_from_json(const nlohmann::json& j);

/// What one scene's tasks use, counted task by task.
class CoverageCount {
 public:
  void add(const Task& task);
  /// Per scene: items (of `items`) in Levels 1-2 and in any task, seen items with look-alikes and
  /// those of them in some Level 2 task, the share of Level 2 from its three largest source
  /// platforms, distinct source platforms, nouns and reference phrases of Levels 1-2; the items
  /// left out by name.
  nlohmann::json report(const std::vector<CoverageItem>& items) const;

 private:
  std::set<std::string> in_levels_1_2_, in_level_2_, in_any_;
  std::map<std::string, long> level_2_sources_;
  std::set<std::string> sources_1_2_, phrases_1_2_, nouns_1_2_;
  long level_2_ = 0;
};

}  // namespace mtg::tasks
