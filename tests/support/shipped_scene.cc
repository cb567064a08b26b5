#include "tests/support/shipped_scene.h"

#include <limits>

#include "core/episode/remix.h"
#include "core/geom/polygon.h"
#include "core/graph/build.h"
#include "core/scene/scene_loader.h"
#include "tests/support/shipped_data.h"

namespace mtg::testing {

ShippedScene load_shipped_scene(const std::string& name) {
  scene::MeshCache meshes(scene::MeshLoadOptions{.keep_textures = false});
  ShippedScene out{scene::load_scene(*shipped_dataset(), name, meshes), {}};
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, graph::kDefaultProfile);
  out.graph = graph::build_scene_graph(out.scene, graph_options);
  return out;
}

graph::ObjectId smallest_item(const graph::SceneGraph& g, const episode::WorldState& s) {
  graph::ObjectId smallest;
  double least = std::numeric_limits<double>::infinity();
  for (const graph::PlatformId p : g.navigable) {
    for (const graph::ObjectId o : episode::pickable_on(g, s, p)) {
      const double area = geom::area(geom::Region{{s.objects[o].footprint}});
      if (area < least) least = area, smallest = o;
    }
  }
  return smallest;
}

ShippedScene load_remixed_scene(const std::string& name, std::uint64_t remix_seed) {
  ShippedScene out = load_shipped_scene(name);
  const auto moved = episode::remix_items(out.graph, remix_seed);
  for (scene::ObjectInstance& o : out.scene.objects) {
    const auto it = moved.find(o.name);
    if (it != moved.end() && !o.articulated) o.X_WO.translation() += it->second;
  }
  out.scene.name = name + "_remix_" + std::to_string(remix_seed);
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, graph::kDefaultProfile);
  out.graph = graph::build_scene_graph(out.scene, graph_options);
  return out;
}

}  // namespace mtg::testing
