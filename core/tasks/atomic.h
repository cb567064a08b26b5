#pragma once
// Atomic tasks (Levels 1 and 2): every item on a navigable platform x every navigable
// destination x every goal that some placement the agent can choose achieves there.
//
// Validity by construction: for each (item, destination) the generator plays the agent's own
// moves (go to the source, pick, go to the destination, startplace) and resolves every offered
// placement key with the same code the runtime uses; a goal becomes a task only when the judge's
// predicate accepts the resulting state, and the keys that got there are its oracle plan.

#include <string>
#include <vector>

#include "core/episode/goals.h"
#include "core/episode/world_state.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

struct AtomicTask {
  episode::AtomicGoal goal;
  std::vector<std::string> oracle;  // l<src>, o<k>, l<dst>, startplace, <target> (no call_end)
  std::string key;                  // canonical identity: item + goal (no duplicates per set)
};

struct AtomicFilter {
  std::vector<int> items;         // only these items (empty: all)
  std::vector<int> destinations;  // only these destination platforms (empty: all)
};

/// All atomic tasks of state `s` (nothing held), in a deterministic order: source platforms by
/// label, items in o-order, destinations by label, placement keys in order.
std::vector<AtomicTask> enumerate_atomic(const graph::SceneGraph& g, const episode::WorldState& s,
                                         const TaskOptions& options, const AtomicFilter& filter = {});

/// Plays an atomic task's oracle plan on `s` (which must be the state it was generated for or
/// one where its keys still apply) with the episode rules; true when the goal then holds.
bool play_oracle(const graph::SceneGraph& g, episode::WorldState& s, const AtomicTask& task,
                 const TaskOptions& options);

/// Whether `object` is not unique on furniture platform `platform` under the rule (objects on
/// the platform and on things standing on it count; `ignore` is left out, e.g. the moved item).
bool ambiguous(const graph::SceneGraph& g, const episode::WorldState& s, int object, int platform,
               Ambiguity rule, int ignore = -1);

}  // namespace mtg::tasks
