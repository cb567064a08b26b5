#pragma once
// Level 4, outcome-based tasks: our own template library (templates/outcome_templates.json,
// compiled in) instantiated against the scene graph. Each template has a kind that fixes what its
// placeholders bind to and the goal predicates the judge checks; the 31 kinds, their goals and
// what they need of a scene are tabled in docs/tasks.md ("Level 4") and in outcome.cc's kinds().
//
// Each kind runs once over every binding its scene offers (object-level placeholders drawn with
// the seed) and words each task with one of its phrasings, drawn by the goal among those whose
// placeholders are all bound. An object placeholder reads "<noun> from <platform>", with a
// reference when the object has look-alikes there ("leftmost book from shelf_2"); a category
// placeholder means every item its word names (covers included) in its scope, and the goal must
// ask for exactly the objects the words pick out (checked for every task). Every object the
// oracle picks stands on a platform the text names. The default feasibility check is rule-based:
// a greedy plan (the agent's own keys, played with the episode rules) must reach the goal; the
// step limit is set to fit it with room; recorded votes (feasibility.h) can veto tasks afterwards.
// No kind keeps more than `level4_max_kind_share` of the tasks.

#include <string>
#include <vector>

#include "core/episode/goals.h"
#include "core/render/visibility.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

enum class OutcomeKind {
  kGatherCategory,
  kConsolidate,
  kClearPlatform,
  kClearCategory,
  kArrangeOn,
  kTogether,
  kSetUp,
  kPutAway,
  kSort,
  kMoveLayer,
  kPair,
  kSwap,
  kLeaveExactly,
  kBringSome,
  kKeepOne,
  kSplit,
  kSpreadOut,
  kSeparate,
  kJoinKind,
  kGroupAround,
  kClearAround,
  kTwoPairs,
  kMoveAll,
  kKeepOnly,
  kThinOut,
  kLayOut,
  kPutInside,
  kBesideKind,
  kAllButOne,
  kFillEmpty,
  kGatherTwo,
};
/// The kind's name in template files and task types ("gather_category", ...).
const char* to_string(OutcomeKind kind);

struct OutcomeTemplate {
  std::string id;
  std::string family;  // arrange, gather, clear, set_up, sort, pair
  OutcomeKind kind = OutcomeKind::kGatherCategory;
  std::string text;
};

/// Loads "builtin" (the compiled-in library) or a JSON file of the same format.
/// @throws mtg::Error naming the template and the placeholder for an unknown kind, an unknown
/// placeholder or a missing required one.
std::vector<OutcomeTemplate> load_templates(const std::string& source);

struct OutcomeTask {
  const OutcomeTemplate* tmpl = nullptr;
  std::string text;
  episode::OutcomeGoal goal;
  std::vector<std::string> oracle;  // without call_end
  int moved = 0;  // objects the goal lists that the plan moves (a stack's items each count)
  std::vector<Identification> identify;  // named objects with look-alikes
};

/// Drops (DropCounts): "vague" when the words of a text pick out other objects than its goal's
/// (e.g. "all the books in the house" while one book stands where the agent cannot go),
/// "unidentifiable" when a named object has look-alikes no reference tells apart, "occluded"
/// (with `seeing`) when an object the words name or count is not clearly visible in its
/// platform's arrival view, "trivial" when the outcome already holds.
std::vector<OutcomeTask> generate_outcomes(const graph::SceneGraph& g, const episode::WorldState& initial,
                                           const std::vector<OutcomeTemplate>& templates, const TaskOptions& options,
                                           std::vector<std::string>& warnings, DropCounts& dropped,
                                           episode::PlacementMemo* memo = nullptr,
                                           const render::VisibilityOracle* seeing = nullptr);

}  // namespace mtg::tasks
