#include "orchestrator/run/goal_check.h"

#include "core/episode/goals.h"
#include "core/graph/scene_cache.h"
#include "core/util/error.h"
#include "core/util/log.h"

namespace mtg::orchestrator {

void check_goals(const std::vector<const tasks::Task*>& tasks, const std::string& profile, graph::PlatformRules rules,
                 const std::string& data_dir, const std::string& origin, MissingScene missing,
                 graph::SceneCache* shared) {
  graph::SceneCache own(profile, rules);
  graph::SceneCache& scenes = shared != nullptr ? *shared : own;
  for (const tasks::Task* t : tasks) {
    const graph::SceneGraph* g = nullptr;
    try {
      g = &scenes.get(t->scene, data_dir);
    } catch (const Error& e) {
      if (missing == MissingScene::kSkip) {
        log::info(std::string("goals not checked here (") + e.what() + "); each worker checks its episodes");
        return;
      }
      throw;
    }
    try {
      (void)episode::task_goal_from_json(*g, t->goal);
    } catch (const Error& e) {
      throw Error(origin + ": task " + t->id + ": its goal does not hold in scene " + t->scene + ": " + e.what());
    } catch (const nlohmann::json::exception& e) {
      throw Error(origin + ": task " + t->id + ": its goal is malformed: " + e.what());
    }
  }
}

}  // namespace mtg::orchestrator
