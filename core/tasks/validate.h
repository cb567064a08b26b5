#pragma once
// Checking a stored task against the episode rules and the generator's promises
// (docs/tasks.md, "What every task guarantees"): its oracle plan, played from the initial state
// with the episode rules (anchors protected, step limit enforced), reaches the goal; no goal, and
// no Level 3 step, holds when it starts; every look-alike's reference names exactly its object
// where the step starts; every placement fits under the clearance and lies where the task says,
// with the margin it claims. Used by the validity tests.

#include <string>
#include <vector>

#include "core/graph/scene_graph.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

struct PlayResult {
  bool success = false;
  int steps = 0;
  std::string failure;  // first problem ("" on success)
};

/// Plays the oracle plan and judges the end state.
PlayResult play_task(const graph::SceneGraph& g, const Task& task, const TaskOptions& options);

/// Where an atomic or Level 3 task's part `part` starts, its oracle plan played up to there: the
/// state the agent arrives at the item's platform in, or, `holding`, the state once it picked the
/// item (where it arrives at the destination with it). @throws mtg::Error for an outcome task, a
/// part it does not have, or a plan that does not play.
episode::WorldState start_of_part(const graph::SceneGraph& g, const Task& task, const TaskOptions& options, int part,
                                  bool holding);

/// Every broken promise of the task, one line each (empty when it keeps them all). A direction's
/// key must be offered in the task's own words ("front-right of object 3"), a next-to's as one of
/// its anchor's own free spaces.
std::vector<std::string> audit_task(const graph::SceneGraph& g, const Task& task, const TaskOptions& options);

}  // namespace mtg::tasks
