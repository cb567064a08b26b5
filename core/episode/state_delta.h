#pragma once
// A world state as its changes from the state the graph starts from: only what an episode has
// changed (moved objects, reordered platforms, the hand, where the robot stands), with objects
// and platforms named. Another process with the same scene graph rebuilds the identical
// WorldState from it: the renderer numbers items and targets from it exactly as the scene-graph
// service does (docs/render.md, "State"). It crosses the bus typed, as world_state_delta_t
// (bus/convert); names, not indices, because the two processes' graphs are separate objects.

#include <string>
#include <vector>

#include "core/episode/world_state.h"

namespace mtg::episode {

/// An object whose state differs from the start: all of ObjectState, its parent by name.
struct MovedObject {
  std::string object;
  std::string parent;  // "" = none (held, floor or structure)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  geom::Ring footprint;
  double bottom = 0.0;
  double top = 0.0;
  int placed_side = -1;
};

/// A platform whose list of resting objects differs from the start (its whole new list).
struct PlatformOrder {
  std::string platform;
  std::vector<std::string> objects;
};

/// A platform carried along with its item (non-zero offset from where the graph found it).
struct PlatformOffset {
  std::string platform;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};

struct StateDelta {
  Phase phase = Phase::kStart;
  std::string at;    // platform the robot stands at ("" = none)
  int side = -1;     // -1..3
  std::string held;  // object in hand ("" = none)
  int steps = 0;
  std::vector<MovedObject> moved;          // in object order
  std::vector<PlatformOrder> reordered;    // in platform order
  std::vector<PlatformOffset> offsets;     // in platform order
  Numbering numbering = Numbering::kStable;
  /// Stable numbering: furniture platforms whose items have changed, each with its items by
  /// number ("" where a number is retired); in platform order.
  std::vector<PlatformOrder> numbered;
};

/// The changes of `s` against initial_state(g). Applying them gives `s` back bit for bit.
StateDelta state_delta(const graph::SceneGraph& g, const WorldState& s);

/// initial_state(g) with `delta` applied; a default StateDelta gives the initial state.
/// @throws mtg::Error naming the field and the unknown object or platform, or the bad value.
WorldState apply_delta(const graph::SceneGraph& g, const StateDelta& delta);

}  // namespace mtg::episode
