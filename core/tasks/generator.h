#pragma once
// All four levels for one scene graph: the entry point of `mtg tasks` and the task-generator
// service. Deterministic in (scene, generator version, options incl. seed).

#include <functional>
#include <string>
#include <vector>

#include "core/graph/scene_graph.h"
#include "core/render/visibility.h"
#include "core/tasks/feasibility.h"
#include "core/tasks/task.h"

namespace mtg::tasks {

struct GenerationResult {
  TaskSet set;
  std::vector<Vote> votes;  // Level 4 votes (rule-based, plus recorded ones given)
};

/// Takes the tasks of a scene as they are made, in the order they are numbered (Levels 1 and 2
/// interleave), a batch at a time, so that no one holds the whole set (TaskDbWriter::make_chunks).
using TaskSink = std::function<void(std::vector<Task>)>;

/// @throws mtg::Error for an unknown level, a scene with no navigable platform, or a template
/// library that does not load.
/// `jobs` threads share the work of Levels 1-3, and with more than one, Level 4 runs on one more
/// thread alongside them; the result is the same for any number.
/// With a `sink`, the tasks go to it as they are made and the result's set holds none of them.
/// `seeing` answers what the arrival views show; it is needed when options.visibility is set
/// (@throws mtg::Error without it).
GenerationResult generate_tasks(const graph::SceneGraph& g, const TaskOptions& options,
                                const std::vector<Vote>& recorded_votes = {},
                                const std::vector<VoteBatch>& live_voters = {}, int jobs = 1,
                                const TaskSink& sink = {}, const render::VisibilityOracle* seeing = nullptr);

/// The same with the scene's meshes, from which the visibility rules of options.visibility see.
GenerationResult generate_tasks(const scene::Scene& scene, const graph::SceneGraph& g, const TaskOptions& options,
                                const std::vector<Vote>& recorded_votes = {},
                                const std::vector<VoteBatch>& live_voters = {}, int jobs = 1,
                                const TaskSink& sink = {});

/// The platforms an agent can go to and what stands on them, one line each (for voters).
std::string describe_scene(const graph::SceneGraph& g);

/// "1,2,4" -> {1, 2, 4}. @throws mtg::Error naming an unknown level.
std::set<int> parse_levels(const std::string& text);

}  // namespace mtg::tasks
