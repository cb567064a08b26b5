#include "tests/support/graph_fixtures.h"

#include "core/scene/scene_loader.h"

namespace mtg::testing {

void add_table(FixtureDataset& fx, const std::string& name, double sx, double sy) {
  std::vector<FixtureDataset::Box> parts = {{{sx, 0.04, sy}, {0, 0.70, 0}}};
  for (const double x : {-sx / 2 + 0.05, sx / 2 - 0.05}) {
    for (const double z : {-sy / 2 + 0.05, sy / 2 - 0.05}) parts.push_back({{0.04, 0.70, 0.04}, {x, 0, z}});
  }
  fx.add_object_config("toy_" + name, fx.add_boxes_mesh(name, parts));
}

Eigen::Vector3d hab(double x, double y, double z) { return {x, z, -y}; }

BuiltScene build_fixture_scene(const FixtureDataset& fx, const std::string& name) {
  scene::MeshCache cache;
  BuiltScene b{scene::load_scene(scene::index_dataset(fx.root()), name, cache), {}};
  graph::GraphOptions options;
  graph::apply_profile(options, "none");
  b.graph = graph::build_scene_graph(b.scene, options);
  return b;
}

BuiltScene two_tables(FixtureDataset& fx) {
  add_table(fx, "table");
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_scene("two_tables", {{"object_instances",
                               {FixtureDataset::instance("toy_table", {0, 0, 0}),
                                FixtureDataset::instance("toy_box", hab(-0.3, 0, 0.75)),
                                FixtureDataset::instance("toy_box", hab(0.0, 0, 0.75)),
                                FixtureDataset::instance("toy_box", hab(0.3, 0, 0.75)),
                                FixtureDataset::instance("toy_table", hab(3, 0, 0))}}});
  return build_fixture_scene(fx, "two_tables");
}

}  // namespace mtg::testing
