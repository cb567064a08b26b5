#pragma once
// The questions a model agent is asked in one episode, found without a bus or a renderer: the
// task's oracle plan played on the scene graph as the scene-graph service plays each answer
// (episode::step_episode), each observation's situation text, offered keys and hint as that
// service builds them, its images as the renderer names them (render::observation_views, the
// close-ups, the parts of a long platform), and each step's user text filled in by the adapter's
// own step_text. The cost estimate (cost_estimate.h) counts them.
//
// What cannot be known without drawing: the zoomed close-ups of crowded parts (view_zoom) and the
// words the marked view's caption says about them. Images carry one placeholder byte: which
// images are sent matters here, not what they show.

#include <string>
#include <vector>

#include "agents/vlm/cost_estimate.h"
#include "agents/vlm/prompt.h"
#include "agents/vlm/settings.h"
#include "core/episode/rules.h"
#include "core/graph/scene_graph.h"
#include "core/tasks/task.h"
#include "mtg/observation_t.hpp"

namespace mtg::vlm {

struct WalkOptions {
  int step_limit = 15;        // the episode's: the larger of the plan's and the task's
  bool render = true;         // observations carry images
  bool object_names = false;  // as the plan says (episode::RuleOptions)
  episode::LookalikeAid lookalike_aid = episode::LookalikeAid::kBoth;  // as the plan says
  episode::Numbering numbering = episode::Numbering::kStable;          // as the plan says
  int image_width = 640;
  int image_height = 480;
};

/// The observations of a model that answers `task`'s oracle plan, and its answers (the plan's
/// keys, then "0" if the plan lacks the final one).
struct WalkedEpisode {
  std::vector<mtg::observation_t> observations;
  std::vector<std::string> replies;
  int step_limit = 15;
};

/// @throws mtg::Error when the task's goal does not resolve in `g`.
WalkedEpisode walk_oracle(const graph::SceneGraph& g, const tasks::Task& task, const WalkOptions& options);

/// What each question of `walked` costs, with the templates and settings the adapter uses.
EpisodePrompts episode_prompts(const WalkedEpisode& walked, const PromptSet& prompts, const VlmSettings& settings);

}  // namespace mtg::vlm
