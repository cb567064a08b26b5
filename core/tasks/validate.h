#pragma once
// Checking a stored task against the episode rules: play its oracle plan from the initial state
// (the task's anchors protected, its step limit enforced) and ask the judge's predicate whether
// the goal holds. Used by the validity tests and by `mtg tasks check`.

#include <string>

#include "core/graph/scene_graph.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

struct PlayResult {
  bool success = false;
  int steps = 0;
  std::string failure;  // first problem ("" on success)
};

PlayResult play_task(const graph::SceneGraph& g, const Task& task, const TaskOptions& options);

}  // namespace mtg::tasks
