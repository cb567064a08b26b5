#pragma once
// Conversions between the core types and the mtg message types. core/ never sees LCM; the
// services call these at their edges. Objects and platforms travel by name.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/episode/judge.h"
#include "core/episode/rules.h"
#include "core/episode/state_delta.h"
#include "core/episode/transcript.h"
#include "core/episode/usage.h"
#include "core/graph/scene_graph.h"
#include "core/render/image_request.h"
#include "core/render/view.h"
#include "core/tasks/task.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"
#include "mtg/image_t.hpp"
#include "mtg/render_request_t.hpp"
#include "mtg/render_view_t.hpp"
#include "mtg/state_update_t.hpp"
#include "mtg/task_t.hpp"
#include "mtg/world_state_delta_t.hpp"

namespace mtg::bus {

/// What an agent may see of a task (id, scene, level, type, text).
mtg::task_t to_message(const tasks::Task& task);
/// What only the judge, the scene-graph service and the oracle see (header left to the caller).
mtg::episode_truth_t truth_message(const tasks::Task& task);
/// What an episode's two halves say of its task: the public half (task_t) and the truth
/// (episode_truth_t). Deliberately not a tasks::Task: the bus carries no oracle placements,
/// template or summary fields, and a Task with those left empty would look whole.
struct EpisodeTask {
  std::string id;
  std::string scene;
  int level = 0;
  std::string type;
  std::string text;
  nlohmann::json goal;                            // as in the task database (docs/tasks.md)
  std::vector<std::string> oracle;                // the plan's keys
  std::vector<tasks::Identification> identify;   // look-alikes and how the text names them
};
/// @throws mtg::Error naming the task when the truth belongs to another task or its JSON does
/// not parse.
EpisodeTask from_messages(const mtg::task_t& task, const mtg::episode_truth_t& truth);

/// @throws mtg::Error naming an object or platform the graph does not know.
mtg::state_update_t to_message(const graph::SceneGraph& g, const episode::WorldState& s,
                               const episode::StateUpdate& u);
episode::StateUpdate from_message(const graph::SceneGraph& g, const mtg::state_update_t& m);

/// The episode rules an episode start asks for (its step limit, object naming and look-alike aid;
/// the defaults otherwise). The scene-graph service and `mtg rejudge` must step an episode alike.
/// @throws mtg::Error on a look-alike aid it does not know.
episode::RuleOptions episode_rules(const mtg::episode_start_t& start);
/// episode_start_t's code for `aid` (AID_BOTH, AID_IMAGE, AID_WORDS).
std::int8_t to_message(episode::LookalikeAid aid);
/// episode_start_t::NUMBERING_* (the same values in world_state_delta_t).
std::int8_t to_message(episode::Numbering numbering);

/// What the rules need of an agent's action.
episode::AgentAnswer to_answer(const mtg::agent_action_t& action);

/// A world state's changes, to and from the bus (names stay names; the receiver resolves them
/// against its own graph with episode::apply_delta).
mtg::world_state_delta_t to_message(const episode::StateDelta& d);
episode::StateDelta from_message(const mtg::world_state_delta_t& m);

/// A render request as the renderer takes it (views by name, typed).
/// @throws mtg::Error naming an unknown view or mark kind.
render::ImageRequest from_message(const mtg::render_request_t& m);
/// One view of a render request: the graph's ids become names.
mtg::render_view_t to_message(const graph::SceneGraph& g, const render::ViewRequest& v);
/// An encoded image with its content hash.
mtg::image_t to_message(const render::EncodedImage& e);

/// An answer's cost figures, to and from the action that carries them.
void set_usage(mtg::agent_action_t& action, const episode::AnswerUsage& usage);
episode::AnswerUsage answer_usage(const mtg::agent_action_t& action);
/// An episode's summed cost figures, to and from its result.
void set_usage(mtg::episode_result_t& result, const episode::EpisodeUsage& usage);
episode::EpisodeUsage episode_usage(const mtg::episode_result_t& result);

/// Fills the verdict fields of an episode result (header and identity left to the caller).
void fill_result(const episode::Verdict& v, mtg::episode_result_t& r);

}  // namespace mtg::bus
