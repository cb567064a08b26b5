#pragma once
// Every task's goal resolves in its scene as this machine loads it (`mtg run` before anything is
// written, `mtg suite verify`): a goal that names an object or platform the scene lacks would
// otherwise give an error row per episode after the run started.

#include <string>
#include <vector>

#include "core/graph/scene_cache.h"
#include "core/tasks/task.h"

namespace mtg::orchestrator {

enum class MissingScene {
  kFail,  ///< a scene that does not load is an error
  kSkip,  ///< ... ends the check early, said in one log line (a coordinator whose workers hold the data)
};

/// @throws mtg::Error naming `origin`, the task and why ("<origin>: task X: its goal does not
/// hold in scene S: ..."), or the scene that cannot be loaded (with MissingScene::kFail).
/// Scenes are loaded through `scenes` when given (a command that loads them again after), else
/// through a cache of its own with `profile` and `rules` (as the tasks were planned).
void check_goals(const std::vector<const tasks::Task*>& tasks, const std::string& profile, graph::PlatformRules rules,
                 const std::string& data_dir, const std::string& origin, MissingScene missing,
                 graph::SceneCache* scenes = nullptr);

}  // namespace mtg::orchestrator
