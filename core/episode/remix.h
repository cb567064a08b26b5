#pragma once
// A new arrangement of a scene's items, for apartments no one has tuned anything on (docs/scene.md,
// "Held-out arrangements"): every item standing on a navigable furniture platform, with whatever
// rests on it, is put in a seeded order on a seeded navigable platform where it fits, at one of the
// places the agent itself could choose there (a free space or a grid cell, resolved by the
// episode's own placement rules), so nothing overlaps and everything stands on a surface. The
// furniture stays where it is. `mtg scene remix` writes the result as a scene file.

#include <cstdint>
#include <map>
#include <string>

#include "core/episode/world_state.h"

namespace mtg::episode {

/// Each moved object's displacement in the world (Z-up), by name; objects that stay are absent.
std::map<std::string, Eigen::Vector3d> remix_items(const graph::SceneGraph& g, std::uint64_t seed);

}  // namespace mtg::episode
