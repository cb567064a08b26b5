#include "agents/vlm/prompt_walk.h"

#include <algorithm>
#include <cctype>

#include "agents/vlm/conversation.h"
#include "core/episode/goals.h"
#include "core/episode/rules.h"
#include "core/episode/transcript.h"
#include "core/render/close_ups.h"
#include "core/render/view.h"
#include "core/tasks/lookalike_aid.h"

namespace mtg::vlm {
namespace {

void add_image(std::vector<mtg::image_t>& out, const std::string& role, const std::string& caption, int width,
               int height) {
  mtg::image_t img{};
  img.role = role;
  img.caption = caption;
  img.encoding = "png";
  img.width = width;
  img.height = height;
  img.data = {0};  // step_text lists only images that have bytes
  img.nbytes = 1;
  out.push_back(std::move(img));
}

// The caption the renderer gives a part of a long platform (image_renderer.cc, part_caption).
std::string part_caption(const render::PlatformPicture& picture, const std::string& platform) {
  std::string words = render::part_words(picture);
  words[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(words[0])));
  return words + " of " + platform + ", seen from where you stand, numbered as in the whole view.";
}

// The images the renderer makes of one view, by role: the plain picture and, when marked, its
// marked copy; for a platform, one pair per picture (the whole, then each part of a long one).
void add_view_images(const graph::SceneGraph& g, const episode::WorldState& s, const render::ViewRequest& v,
                     std::vector<mtg::image_t>& out) {
  const bool marked = v.marks != render::MarkKind::kNone;
  std::string role = "view";
  switch (v.view) {
    case render::ViewKind::kTopdown: role = "topdown"; break;
    case render::ViewKind::kItem: role = "item"; break;
    case render::ViewKind::kFocus: role = "focus"; break;
    case render::ViewKind::kPlatform: {
      const int side = v.side >= 0 ? v.side : std::max(0, g.platforms[v.platform].default_side);
      const auto pictures = render::platform_pictures(g, s, v.platform, side, v.width, v.height);
      for (std::size_t k = 0; k < pictures.size(); ++k) {
        const std::string caption = k == 0 ? v.caption : part_caption(pictures[k], g.platforms[v.platform].name);
        add_image(out, "view", caption, v.width, v.height);
        if (marked) add_image(out, "view_marked", caption, v.width, v.height);
      }
      return;
    }
  }
  add_image(out, role, v.caption, v.width, v.height);
  if (marked) add_image(out, role + "_marked", v.caption, v.width, v.height);
}

// The observation the scene-graph service sends in state `s` (episode_host.cc,
// publish_observation and send_observation).
mtg::observation_t observation_at(const graph::SceneGraph& g, const episode::WorldState& s, const tasks::Task& task,
                                  const std::string& task_text, const std::string& hint, const episode::RuleOptions& rules,
                                  const WalkOptions& options, int held_number, render::CloseUpsShown& shown) {
  mtg::observation_t obs{};
  obs.step = s.steps;
  obs.step_limit = rules.step_limit;
  obs.done = false;
  obs.task_text = task_text;
  obs.hint = hint;
  obs.text = episode::observation_text(g, s, rules);
  for (const episode::ActionOption& option : episode::action_space(g, s, rules)) {
    mtg::action_option_t a{};
    a.key = option.key;
    a.description = option.description;
    obs.actions.push_back(std::move(a));
  }
  obs.n_actions = static_cast<int32_t>(obs.actions.size());
  if (options.render) {
    std::vector<render::ViewRequest> views =
        render::observation_views(s, options.image_width, options.image_height, rules.min_region_size);
    render::add_close_ups(g, s, task.identify, held_number, options.image_width, options.image_height, shown, views,
                          options.lookalike_aid);
    for (const render::ViewRequest& v : views) add_view_images(g, s, v, obs.images);
  }
  obs.n_images = static_cast<int32_t>(obs.images.size());
  return obs;
}

}  // namespace

WalkedEpisode walk_oracle(const graph::SceneGraph& g, const tasks::Task& task, const WalkOptions& options) {
  WalkedEpisode out;
  out.step_limit = options.step_limit;
  episode::RuleOptions rules;
  rules.step_limit = options.step_limit;
  rules.object_names = options.object_names;
  const episode::TaskConstraints constraints{episode::task_goal_from_json(g, task.goal).protected_objects()};
  rules.lookalike_aid = options.lookalike_aid;
  rules.numbering = options.numbering;
  episode::WorldState s = episode::initial_state(g, rules.numbering);
  const tasks::TaskWords words = tasks::task_words(task.id, task.text, task.identify, options.lookalike_aid, options.render);
  std::string hint = words.hint;
  render::CloseUpsShown shown;
  int held_number = 0;
  std::size_t next = 0;
  // Ends with "0" or at the step limit, whatever the plan's keys do.
  while (s.phase != episode::Phase::kDone) {
    const std::string key = next < task.oracle.size() ? task.oracle[next++] : "0";
    out.observations.push_back(observation_at(g, s, task, words.text, hint, rules, options, held_number, shown));
    out.replies.push_back(key);
    const episode::EpisodeStep step = episode::step_episode(g, s, {key, true, false}, constraints, rules);
    hint = step.hint;
    if (step.outcome.picked.valid()) held_number = std::stoi(key.substr(1));  // "o<N>"
    if (!s.held.valid()) held_number = 0;
  }
  return out;
}

EpisodePrompts episode_prompts(const WalkedEpisode& walked, const PromptSet& prompts, const VlmSettings& settings) {
  EpisodePrompts p;
  p.step_limit = walked.step_limit;
  // As Conversation renders it.
  p.system_chars = static_cast<std::int64_t>(
      render_template(prompts.system,
                      {{"step_limit", std::to_string(walked.step_limit)}, {"directions", episode::direction_convention()}},
                      prompts.dir + "/system.txt")
          .size());
  for (std::size_t i = 0; i < walked.observations.size(); ++i) {
    const mtg::observation_t& obs = walked.observations[i];
    StepPrompt step;
    step.user_chars = static_cast<std::int64_t>(step_text(prompts, settings, obs).size());
    step.reply_chars = i < walked.replies.size() ? static_cast<std::int64_t>(walked.replies[i].size()) : 0;
    for (const mtg::image_t& img : obs.images) {
      const bool wanted =
          std::find(settings.image_roles.begin(), settings.image_roles.end(), img.role) != settings.image_roles.end();
      step.images += wanted && !img.data.empty() ? 1 : 0;
    }
    p.solved.push_back(step);
  }
  return p;
}

}  // namespace mtg::vlm
