#include "orchestrator/run/run_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "agents/vlm/cost_estimate.h"
#include "agents/vlm/model_spec.h"
#include "agents/vlm/prompt.h"
#include "agents/vlm/prompt_walk.h"
#include "core/graph/scene_cache.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;
using Stratum = std::pair<std::string, int>;  // scene, level

// What a resume skips: the episodes with a verdict (a given-up one runs again).
std::set<bus::EpisodeId> scored_in(const fs::path& run_dir) {
  std::set<bus::EpisodeId> out;
  if (run_dir.empty() || !fs::exists(run_dir / "results.sqlite")) return out;
  for (const EpisodeRow& row : read_results(run_dir / "results.sqlite")) {
    if (row.status == "scored") out.insert(row.episode_id);
  }
  return out;
}

}  // namespace

nlohmann::json estimate_plan(const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks,
                             const vlm::VlmOptions& model_options, const fs::path& run_dir,
                             graph::SceneCache* shared) {
  if (std::none_of(plan.agents.begin(), plan.agents.end(), [](const std::string& a) { return vlm::is_model_spec(a); })) {
    return nullptr;
  }
  const vlm::VlmSettings settings = model_options.resolve();
  const vlm::PromptSet prompts =
      settings.prompts_dir.empty() ? vlm::PromptSet::builtin() : vlm::PromptSet::load(settings.prompts_dir);
  vlm::EstimateInput in;
  in.settings = settings;
  in.prices = settings.prices_file.empty() ? vlm::PriceTable::builtin() : vlm::PriceTable::from_file(settings.prices_file);
  in.images = plan.render;
  in.image_width = plan.image_width;
  in.image_height = plan.image_height;
  in.prompt_version = prompts.version;

  const std::set<bus::EpisodeId> scored = scored_in(run_dir);
  std::vector<std::pair<const PlannedEpisode*, const tasks::Task*>> todo;
  for (const PlannedEpisode& e : plan.episodes) {
    if (!vlm::is_model_spec(e.agent) || scored.count(e.id) != 0) continue;
    const auto t = tasks.find(e.task_id);
    if (t == tasks.end()) {
      ++in.not_estimated;
      in.not_estimated_why = "task " + e.task_id + " is not in " + plan.tasks_db;
      continue;
    }
    todo.emplace_back(&e, &t->second);
  }

  // Each task once (every agent asks the same questions), in the plan's order; a large run
  // walks a sample of each scene and level, which is what its figures depend on.
  graph::SceneCache own(plan.profile, plan.platform_rules);
  graph::SceneCache& scenes = shared != nullptr ? *shared : own;
  std::map<std::string, vlm::EpisodePrompts> walked;                     // task id -> its questions
  std::map<Stratum, std::vector<const vlm::EpisodePrompts*>> by_stratum;  // map values do not move
  std::map<std::string, std::string> not_here;                           // scene -> why it does not load
  for (const auto& [planned, t] : todo) {
    if (walked.count(t->id) != 0 || not_here.count(t->scene) != 0) continue;
    std::vector<const vlm::EpisodePrompts*>& sample = by_stratum[{t->scene, t->level}];
    if (sample.size() >= kWalksPerStratum) continue;
    const graph::SceneGraph* g = nullptr;
    try {
      g = &scenes.get(t->scene, plan.data_dir);
    } catch (const Error& e) {
      not_here.emplace(t->scene, e.what());
      continue;
    }
    vlm::WalkOptions w;
    w.step_limit = std::max(plan.step_limit, t->step_limit);
    w.render = plan.render;
    w.object_names = plan.object_names;
    w.lookalike_aid = plan.lookalike_aid;
    w.numbering = plan.numbering;
    w.image_width = plan.image_width;
    w.image_height = plan.image_height;
    try {
      const auto it = walked.emplace(t->id, vlm::episode_prompts(vlm::walk_oracle(*g, *t, w), prompts, settings)).first;
      sample.push_back(&it->second);
    } catch (const Error& e) {
      log::warn("cost estimate: task " + t->id + " not walked (" + e.what() + "); another task stands in");
    }
  }

  std::vector<const vlm::EpisodePrompts*> every;
  for (const auto& [id, p] : walked) every.push_back(&p);
  std::map<Stratum, std::size_t> turn;
  std::size_t every_turn = 0;
  for (const auto& [planned, t] : todo) {
    if (const auto it = walked.find(t->id); it != walked.end()) {
      in.episodes.push_back({planned->agent, it->second});
      continue;
    }
    const Stratum stratum{t->scene, t->level};
    const std::vector<const vlm::EpisodePrompts*>& sample = by_stratum[stratum];
    const vlm::EpisodePrompts* stand_in = !sample.empty() ? sample[turn[stratum]++ % sample.size()]
                                          : !every.empty() ? every[every_turn++ % every.size()]
                                                           : nullptr;
    if (stand_in == nullptr) {
      ++in.not_estimated;
      in.not_estimated_why = not_here.empty() ? "no task could be walked"
                                              : "scene " + not_here.begin()->first + " does not load here (" +
                                                    not_here.begin()->second + ")";
      continue;
    }
    vlm::EpisodePrompts p = *stand_in;
    p.step_limit = std::max(plan.step_limit, t->step_limit);
    in.episodes.push_back({planned->agent, std::move(p)});
    ++in.stand_ins;
  }
  return vlm::estimate_run(in);
}

int print_estimate(const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks, const vlm::VlmOptions& model_options,
                   const fs::path& run_dir, graph::SceneCache* scenes) {
  const nlohmann::json estimate = estimate_plan(plan, tasks, model_options, run_dir, scenes);
  if (estimate.is_null()) {
    std::printf("no model agent in this run: nothing to estimate (built-in agents call no model)\n");
  } else {
    std::fputs(vlm::estimate_text(estimate).c_str(), stdout);
  }
  return 0;
}

Budget announce_estimate(double max_cost_usd, const RunPlan& plan, const std::map<std::string, tasks::Task>& tasks,
                         const vlm::VlmOptions& model_options, const fs::path& run_dir,
                         graph::SceneCache* scenes) {
  if (!(max_cost_usd >= 0.0) || !std::isfinite(max_cost_usd)) {
    throw Error("--max-cost must be 0 (no cap) or more US dollars, not " + std::to_string(max_cost_usd));
  }
  Budget budget;
  budget.max_cost_usd = max_cost_usd;
  nlohmann::json estimate;
  try {
    estimate = estimate_plan(plan, tasks, model_options, run_dir, scenes);
  } catch (const std::exception& e) {
    // The run does not depend on it; the cap still counts what is spent.
    log::warn(std::string("no cost estimate: ") + e.what() +
              (max_cost_usd > 0.0 ? "; --max-cost counts an episode in flight at its agent's average cost once one "
                                    "has finished"
                                  : ""));
    return budget;
  }
  if (estimate.is_null()) return budget;
  std::fputs(vlm::estimate_text(estimate).c_str(), stdout);
  const auto episodes = estimate["episodes"].get<std::int64_t>();
  const double expected = estimate["total"]["expected"]["cost_usd"].get<double>();
  if (max_cost_usd > 0.0 && episodes > 0 && expected > 0.0) {
    const double per_episode = expected / static_cast<double>(episodes);
    const auto fit = std::min<std::int64_t>(episodes, static_cast<std::int64_t>(max_cost_usd / per_episode));
    std::printf("  --max-cost $%.2f: about %lld of these %lld episode(s) at the expected cost\n", max_cost_usd,
                static_cast<long long>(fit), static_cast<long long>(episodes));
  }
  std::fflush(stdout);
  budget.expected_episode_cost_usd = expected_episode_costs(estimate);
  return budget;
}

std::map<std::string, double> expected_episode_costs(const nlohmann::json& estimate) {
  std::map<std::string, double> out;
  if (!estimate.is_object() || !estimate.contains("agents")) return out;
  for (const auto& [agent, a] : estimate["agents"].items()) out[agent] = a.value("expected_episode_cost_usd", 0.0);
  return out;
}

}  // namespace mtg::orchestrator
