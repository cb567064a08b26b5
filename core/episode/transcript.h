#pragma once
// What happened in an episode step, as the scene-graph service reports it on the bus
// (state_update_t) and as the judge replays it: core types, no LCM.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/episode/rules.h"
#include "core/episode/world_state.h"

namespace mtg::episode {

struct Placement {
  graph::ObjectId object;
  graph::PlatformId platform;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // world translation of the object frame
};

/// The world after one step, for the judge.
struct StateUpdate {
  int step = 0;            // steps used after this action
  std::string key;         // action applied ("" for the initial update)
  graph::PlatformId at_platform;
  int side = -1;
  graph::ObjectId holding;
  graph::ObjectId picked;  // object picked in this step
  std::vector<Placement> placed;
  bool invalid = false;    // invalid or unavailable action
  bool format_error = false;  // the agent's reply held no readable key
  bool provider_error = false;  // the agent's provider failed this step
  bool done = false;
  EndReason end_reason = EndReason::kNone;
};

/// One answer of the agent as the scene-graph service receives it.
struct AgentAnswer {
  std::string key;             // parsed action key ("" if none)
  bool format_ok = true;       // a key could be read from the reply
  bool provider_error = false; // the agent's provider failed: the episode ends ("aborted")
};

struct EpisodeStep {
  StepOutcome outcome;
  StateUpdate update;
  std::string hint;  // for the next observation
};

/// Applies one answer to an episode's world (the rules, plus unreadable replies and provider
/// failures): what the scene-graph service does per agent action, and what `mtg rejudge` replays.
EpisodeStep step_episode(const graph::SceneGraph& g, WorldState& s, const AgentAnswer& answer,
                         const TaskConstraints& constraints, const RuleOptions& rules);

/// The update a step produced (after apply_action), from the state and the outcome.
StateUpdate make_update(const WorldState& s, const std::string& key, const StepOutcome& outcome);

/// Applies an update to a replica of the world (the judge's copy): picks and placements.
/// Placements move the object (and what rests on it) to the reported position on the platform.
void apply_update(const graph::SceneGraph& g, WorldState& replica, const StateUpdate& u);

}  // namespace mtg::episode
