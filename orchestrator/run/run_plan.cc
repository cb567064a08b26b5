#include "orchestrator/run/run_plan.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>

#include "core/tasks/draw.h"

#include "core/util/error.h"
#include "core/util/hash.h"
#include "core/util/json_file.h"
#include "core/util/rng.h"

namespace mtg::orchestrator {

nlohmann::json RunPlan::to_json() const {
  nlohmann::json eps = nlohmann::json::array();
  for (const auto& e : episodes) eps.push_back({{"id", e.id.value()}, {"task", e.task_id}, {"agent", e.agent}, {"seed", e.seed}});
  nlohmann::json j = {{"format", "mtg-run-plan/1"},
                     {"run_id", run_id},
                     {"tasks_db", tasks_db},
                     {"agents", agents},
                     {"scenes", scenes},
                     {"levels", levels},
                     {"limit", limit},
                     {"draw", tasks::to_string(draw)},
                     {"repeat", repeat},
                     {"seed", seed},
                     {"parallel", parallel},
                     {"step_limit", step_limit},
                     {"render", render},
                     {"object_names", object_names},
                     {"lookalike_aid", episode::to_string(lookalike_aid)},
                     {"numbering", episode::to_string(numbering)},
                     {"platform_rules", graph::to_string(platform_rules)},
                     {"image_width", image_width},
                     {"image_height", image_height},
                     {"image_encoding", image_encoding},
                     {"max_attempts", max_attempts},
                     {"episode_timeout_s", episode_timeout_s},
                     {"data_dir", data_dir},
                     {"profile", profile},
                     {"bus_url", bus_url},
                     {"remote", remote},
                     {"recordings", recordings},
                     {"allow_data_mismatch", allow_data_mismatch},
                     {"episodes", eps}};
  if (!provenance.is_null()) j["provenance"] = provenance;
  return j;
}

RunPlan RunPlan::from_json(const nlohmann::json& j, const std::string& origin) {
  const JsonField root(j, origin);
  RunPlan p;
  try {
    p.run_id = root.at("run_id").as_string();
    p.tasks_db = root.at("tasks_db").as_string();
    p.agents = j.at("agents").get<std::vector<std::string>>();
    p.scenes = j.at("scenes").get<std::set<std::string>>();
    p.levels = j.at("levels").get<std::set<int>>();
    p.limit = j.at("limit").get<int>();
    // Plans from before stratified draws drew uniformly (and a resume never draws again).
    p.draw = tasks::draw_kind_from_string(j.value("draw", std::string("uniform")));
    p.repeat = j.value("repeat", 1);  // absent in plans written before --repeat
    p.seed = j.at("seed").get<std::uint64_t>();
    p.parallel = j.at("parallel").get<int>();
    p.step_limit = j.at("step_limit").get<int>();
    p.render = j.at("render").get<bool>();
    p.object_names = j.value("object_names", false);
    // Plans from before the aid was a choice gave words and close-ups.
    p.lookalike_aid = episode::lookalike_aid_from_string(j.value("lookalike_aid", std::string("both")), "lookalike_aid");
    // Plans from before stable numbers ran tasks planned with the release's numbering.
    p.numbering = episode::numbering_from_string(j.value("numbering", std::string("per_state")), "numbering");
    // Plans from before the reach ran tasks planned on whole surfaces.
    p.platform_rules =
        graph::platform_rules_from_string(j.value("platform_rules", std::string("whole_surface")), "platform_rules");
    p.image_width = j.value("image_width", p.image_width);  // absent in plans written before images
    p.image_height = j.value("image_height", p.image_height);
    p.image_encoding = j.value("image_encoding", p.image_encoding);
    p.max_attempts = j.at("max_attempts").get<int>();
    p.episode_timeout_s = j.at("episode_timeout_s").get<double>();
    p.data_dir = j.at("data_dir").get<std::string>();
    p.profile = j.at("profile").get<std::string>();
    p.bus_url = j.at("bus_url").get<std::string>();
    p.remote = j.value("remote", false);  // absent in plans written before multi-host runs
    p.recordings = j.value("recordings", std::string("coordinator"));  // absent before recordings stayed on workers
    p.allow_data_mismatch = j.value("allow_data_mismatch", false);
    if (j.contains("provenance")) p.provenance = j.at("provenance");  // absent in plans written before provenance
    for (const auto& e : j.at("episodes")) {
      p.episodes.push_back({bus::EpisodeId(e.at("id").get<std::int64_t>()), e.at("task").get<std::string>(),
                            e.at("agent").get<std::string>(), e.at("seed").get<std::uint64_t>()});
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(origin + ": malformed run plan (" + e.what() + ")");
  } catch (const Error& e) {
    throw Error(origin + ": malformed run plan (" + e.what() + ")");
  }
  return p;
}

std::string new_run_id(const std::string& name) {
  // Identity, not logic: the one place a run draws entropy from the machine.
  std::random_device entropy;
  char suffix[16];
  std::snprintf(suffix, sizeof(suffix), "-%08x", static_cast<unsigned>(entropy()));
  return name + suffix;
}

RunPlan make_plan(RunPlan plan, const std::map<std::string, tasks::Task>& all_tasks) {
  if (plan.agents.empty()) throw Error("no agent given (e.g. --agent oracle)");
  std::map<std::pair<std::string, int>, std::vector<const tasks::Task*>> groups;
  for (const auto& [id, t] : all_tasks) {
    const bool scene_wanted = plan.scenes.empty() || plan.scenes.count(t.scene) != 0;
    if (scene_wanted && plan.levels.count(t.level)) groups[{t.scene, t.level}].push_back(&t);
  }
  std::vector<const tasks::Task*> chosen;
  for (auto& [key, group] : groups) {
    const auto drawn = tasks::draw_tasks(std::move(group), plan.limit, plan.draw,
                                         tasks::draw_seed(plan.seed, key.first, key.second));
    chosen.insert(chosen.end(), drawn.begin(), drawn.end());
  }
  std::sort(chosen.begin(), chosen.end(), [](const tasks::Task* a, const tasks::Task* b) { return a->id < b->id; });
  if (chosen.empty()) throw Error("no task of the requested scenes and levels in " + plan.tasks_db);
  if (plan.repeat < 1) throw Error("--repeat must be at least 1, not " + std::to_string(plan.repeat));
  plan.episodes.clear();
  plan.episodes.reserve(chosen.size() * plan.agents.size() * static_cast<std::size_t>(plan.repeat));
  std::int64_t id = 0;
  // Repetition outermost: a run cut short has covered every task as often as it could.
  for (int r = 0; r < plan.repeat; ++r) {
    for (const tasks::Task* t : chosen) {
      for (const std::string& agent : plan.agents) {
        plan.episodes.push_back({bus::EpisodeId(id), t->id, agent, derive_seed(plan.seed, static_cast<std::uint64_t>(id))});
        ++id;
      }
    }
  }
  return plan;
}

void save_plan(const RunPlan& plan, const std::filesystem::path& run_dir) {
  write_json_file(run_dir / "plan.json", plan.to_json());
}

RunPlan load_plan(const std::filesystem::path& run_dir) {
  const auto file = run_dir / "plan.json";
  return RunPlan::from_json(read_json_file(file), file.string());
}

}  // namespace mtg::orchestrator
