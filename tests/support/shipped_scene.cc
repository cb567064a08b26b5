#include "tests/support/shipped_scene.h"

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

}  // namespace mtg::testing
