#pragma once
// What a validity audit shows a person for one task, and what it asks (docs/view.md, "mtg
// audit"), as the paper's human check did it: the agent's first observation, then the one it gets
// each time it arrives at a platform along the oracle plan (where the objects the text names are
// numbered), and for each object the text names, "which number is it?". The answers a person
// gives are compared with the numbers the objects really have there. Pure: the images are drawn
// by the caller.

#include <cstdint>
#include <string>
#include <vector>

#include "core/episode/world_state.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

/// `per_level` tasks of each level present (all when fewer), drawn with `seed`, in level then id
/// order; `scene` ("" any) restricts the draw. The draw takes from groups of tasks in turn (an
/// item model on a source platform; a Level 4 template), so it spreads over platforms and nouns.
/// The same tasks, seed and count give the same draw.
std::vector<const Task*> sample_for_audit(const std::vector<Task>& tasks, int per_level, std::uint64_t seed,
                                          const std::string& scene = "");

/// One observation the audit shows: the world as the agent gets it after `after_key` ("" for the
/// first observation), with the step count the agent would have used.
struct AuditObservation {
  std::string after_key;
  episode::WorldState state;
  std::string title;  // "The first observation", "After l12: arriving at shelf_2", ...
  int step = 0;       // index into AuditPlan::steps
};

/// Every state along the plan (before the first key, then after each), with the number the held
/// item had when picked (0: nothing held): what a run's observations would be made from.
struct AuditStep {
  episode::WorldState state;
  int held_number = 0;
};

/// "Which number is it?": `truth` is the o<N> the object has in observation `observation`; for
/// "p<k>.place", "which key puts the item where the task says?", every placement key offered there
/// that meets the part's goal, space-separated (never shown to the person).
struct AuditQuestion {
  std::string id;          // "p0.item", "p0.anchor", "p1.anchor2", "p0.place", "o2.object" (Level 4)
  std::string ask;         // "Which number is the item to move ('the leftmost book')?"
  int observation = 0;     // the observation where it is numbered
  std::string truth;       // "o3"; "5 7" for a placement
};

struct AuditPlan {
  std::vector<AuditStep> steps;
  std::vector<AuditObservation> observations;
  std::vector<AuditQuestion> questions;
};

/// The observations and questions of `task` (its oracle plan played with the episode rules).
/// @throws mtg::Error when the plan does not play.
AuditPlan plan_audit(const graph::SceneGraph& g, const Task& task, const TaskOptions& options);

}  // namespace mtg::tasks
