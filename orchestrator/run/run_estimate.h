#pragma once
// A run's cost and time before its first model call (docs/vlm.md, "Cost before spending"): each
// planned task with a model agent is walked along its oracle plan on this machine's scene graph
// (agents/vlm/prompt_walk.h) and its questions counted (agents/vlm/cost_estimate.h). `mtg run`
// prints it before it starts, `mtg run --estimate` prints it and stops, and --max-cost counts the
// episodes in flight at its expected cost per episode.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "agents/vlm/options.h"
#include "core/graph/scene_cache.h"
#include "core/tasks/task.h"
#include "orchestrator/run/run_engine.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::orchestrator {

/// The estimate (vlm::estimate_run) of the plan's episodes with model agents that `run_dir`
/// has not scored yet (all of them when it holds no results); null when the plan has no model
/// agent. At most kWalksPerStratum tasks per scene and level are walked; the others, and those
/// of a scene that does not load here, take a walked task's figures of the same scene and level
/// (or any walked task's) in turn.
/// @throws mtg::Error when the model settings, prompts or prices cannot be read.
/// Scenes are loaded through `scenes` when given (loaded once per command), else through a cache
/// of its own.
nlohmann::json estimate_plan(const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks,
                             const vlm::VlmOptions& model_options, const std::filesystem::path& run_dir = {},
                             graph::SceneCache* scenes = nullptr);

inline constexpr std::size_t kWalksPerStratum = 64;

/// `mtg run --estimate`: prints the estimate of what a run (or a resume of `run_dir`) would
/// spend, or that there is nothing to estimate. Writes nothing. Returns the exit status (0).
int print_estimate(const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks, const vlm::VlmOptions& model_options,
                   const std::filesystem::path& run_dir = {}, graph::SceneCache* scenes = nullptr);

/// `mtg run` before its first model call: prints the estimate (plans with model agents only)
/// and returns the engine's budget, --max-cost (0 = none) with each agent's expected episode
/// cost. An estimate that cannot be made is said in one line and the run goes on: the budget
/// then counts an episode in flight at its agent's running average once one has finished.
/// @throws mtg::Error for a negative cap.
Budget announce_estimate(double max_cost_usd, const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks,
                         const vlm::VlmOptions& model_options, const std::filesystem::path& run_dir,
                         graph::SceneCache* scenes = nullptr);

/// Each agent's expected cost of one episode in an estimate (estimate_plan).
std::map<std::string, double> expected_episode_costs(const nlohmann::json& estimate);

}  // namespace mtg::orchestrator
