#pragma once
// A shipped apartment loaded as the generator loads it: its scene (meshes without textures) and
// its graph under the default profile. Callers check MTG_REQUIRE_SHIPPED_DATA() first.

#include <string>

#include "core/graph/scene_graph.h"
#include "core/scene/scene.h"

namespace mtg::testing {

struct ShippedScene {
  scene::Scene scene;
  graph::SceneGraph graph;
};

/// @throws mtg::Error when the shipped dataset lacks `name`.
ShippedScene load_shipped_scene(const std::string& name);

}  // namespace mtg::testing
