#include "tests/support/graph_fixtures.h"

#include "core/scene/scene_loader.h"
#include "core/tasks/generator.h"
#include "core/tasks/task_db.h"

namespace mtg::testing {

void add_table(FixtureDataset& fx, const std::string& name, double sx, double sy) {
  std::vector<FixtureDataset::Box> parts = {{{sx, 0.04, sy}, {0, 0.70, 0}}};
  for (const double x : {-sx / 2 + 0.05, sx / 2 - 0.05}) {
    for (const double z : {-sy / 2 + 0.05, sy / 2 - 0.05}) parts.push_back({{0.04, 0.70, 0.04}, {x, 0, z}});
  }
  fx.add_object_config("toy_" + name, fx.add_boxes_mesh(name, parts));
}

Eigen::Vector3d hab(double x, double y, double z) { return {x, z, -y}; }

BuiltScene build_fixture_scene(const FixtureDataset& fx, const std::string& name, graph::PlatformRules rules) {
  scene::MeshCache cache;
  BuiltScene b{scene::load_scene(scene::index_dataset(fx.root()), name, cache), {}};
  graph::GraphOptions options;
  graph::apply_profile(options, "none");
  options.platform_rules = rules;
  b.graph = graph::build_scene_graph(b.scene, options);
  return b;
}

std::string two_tables_task_db(FixtureDataset& fx) {
  const auto built = two_tables(fx);
  tasks::TaskOptions options;
  options.levels = {1, 2, 3};
  options.level3_count = 10;
  const auto generated = tasks::generate_tasks(built.scene, built.graph, options);
  const std::string db = (fx.root() / "tasks.sqlite").string();
  tasks::write_task_db(db, {generated.set}, generated.votes, options);
  return db;
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

graph::ObjectId object_of_template(const graph::SceneGraph& g, const std::string& template_name) {
  for (const graph::ObjectId o : g.objects.ids()) {
    if (g.objects[o].template_name == template_name) return o;
  }
  return {};
}

graph::PlatformId navigable_platform_of(const graph::SceneGraph& g, const std::string& owner_template) {
  const graph::ObjectId owner = object_of_template(g, owner_template);
  for (const graph::PlatformId p : g.platforms.ids()) {
    if (owner.valid() && g.platforms[p].owner == owner && g.platforms[p].navigable) return p;
  }
  return {};
}

BuiltScene render_room(FixtureDataset& fx) {
  const Eigen::Vector3d wood(0.55, 0.36, 0.2), grey(0.6, 0.6, 0.62);
  auto table = [&](const std::string& name, const Eigen::Vector3d& rgb) {
    std::vector<FixtureDataset::Box> parts = {{{1.0, 0.04, 0.6}, {0, 0.70, 0}, rgb}};
    for (const double x : {-0.45, 0.45}) {
      for (const double z : {-0.25, 0.25}) parts.push_back({{0.04, 0.70, 0.04}, {x, 0, z}, rgb * 0.6});
    }
    fx.add_object_config("toy_" + name, fx.add_boxes_mesh(name, parts));
  };
  table("wood_table", wood);
  table("grey_table", grey);
  auto box = [&](const std::string& name, const Eigen::Vector3d& size, const Eigen::Vector3d& rgb) {
    fx.add_object_config("toy_" + name, fx.add_boxes_mesh(name, {{size, Eigen::Vector3d::Zero(), rgb}}));
  };
  box("red_cube", {0.12, 0.12, 0.12}, {0.85, 0.1, 0.1});
  box("green_tower", {0.08, 0.22, 0.08}, {0.1, 0.7, 0.2});
  box("blue_slab", {0.22, 0.05, 0.16}, {0.15, 0.3, 0.9});
  fx.add_object_config("toy_ghost", "../../objects/ghost_is_missing.obj");
  fx.add_scene("render_room", {{"object_instances",
                                {FixtureDataset::instance("toy_wood_table", {0, 0, 0}),
                                 FixtureDataset::instance("toy_red_cube", hab(-0.3, 0.05, 0.75)),
                                 FixtureDataset::instance("toy_green_tower", hab(0.0, 0.12, 0.75)),
                                 FixtureDataset::instance("toy_blue_slab", hab(0.28, -0.08, 0.75), 30.0),
                                 FixtureDataset::instance("toy_ghost", hab(0.0, -0.18, 0.75)),
                                 FixtureDataset::instance("toy_grey_table", hab(2.5, 0, 0))}}});
  return build_fixture_scene(fx, "render_room");
}

}  // namespace mtg::testing
