#pragma once
// A shipped apartment loaded as the generator loads it: its scene (meshes without textures) and
// its graph under the default profile. Callers check MTG_REQUIRE_SHIPPED_DATA() first.

#include <cstdint>
#include <string>

#include "core/episode/world_state.h"
#include "core/graph/scene_graph.h"
#include "core/scene/scene.h"

namespace mtg::testing {

struct ShippedScene {
  scene::Scene scene;
  graph::SceneGraph graph;
};

/// @throws mtg::Error when the shipped dataset lacks `name`.
ShippedScene load_shipped_scene(const std::string& name);
/// Its items rearranged as `mtg scene remix --seed remix_seed` does (a held-out arrangement),
/// named "<name>_remix_<seed>".
ShippedScene load_remixed_scene(const std::string& name, std::uint64_t remix_seed);

/// The pickable item on a navigable platform with the smallest footprint in `s`: held, it leaves
/// the most free spaces to number (placing-view tests).
graph::ObjectId smallest_item(const graph::SceneGraph& g, const episode::WorldState& s);

}  // namespace mtg::testing
