#pragma once
// A world state as JSON, relative to the state the graph starts from: only what an episode has
// changed (moved objects, reordered platforms, the hand, where the robot stands). Another process
// with the same scene graph rebuilds the identical WorldState from it: the renderer numbers items
// and targets from it exactly as the scene-graph service does (docs/render.md, "State").

#include <nlohmann/json.hpp>

#include "core/episode/world_state.h"

namespace mtg::episode {

/// The changes of `s` against initial_state(g). Doubles round-trip exactly.
nlohmann::json state_delta_to_json(const graph::SceneGraph& g, const WorldState& s);

/// initial_state(g) with `delta` applied; null or {} gives the initial state.
/// @throws mtg::Error naming the field and the unknown object or platform.
WorldState state_from_delta_json(const graph::SceneGraph& g, const nlohmann::json& delta);

}  // namespace mtg::episode
