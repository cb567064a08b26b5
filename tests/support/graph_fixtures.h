#pragma once
// Small scenes for graph, episode and task tests, built with FixtureDataset: tables of boxes
// (OBJ meshes) and objects dropped on them. Units: metres; (x, y) world, z up.

#include <string>

#include "core/graph/build.h"
#include "core/scene/scene.h"
#include "tests/support/fixture_dataset.h"

namespace mtg::testing {

/// A table template "toy_<name>": top surface at 0.74 m, size sx (world x) by sy (world y).
void add_table(FixtureDataset& fx, const std::string& name, double sx = 1.0, double sy = 0.6);

/// Habitat translation of world (x, y) at height z.
Eigen::Vector3d hab(double x, double y, double z);

struct BuiltScene {
  scene::Scene scene;
  graph::SceneGraph graph;
};

/// Loads `name` from the fixture and builds its graph (profile "none").
BuiltScene build_fixture_scene(const FixtureDataset& fx, const std::string& name,
                               graph::PlatformRules rules = graph::PlatformRules::kReachedAndSeen);

/// Two tables far apart: table_0 at the origin with three 0.1 m boxes (box_1, box_2, box_3 at
/// x = -0.3, 0, 0.3), and an empty table_4 at x = 3. Scene name "two_tables".
BuiltScene two_tables(FixtureDataset& fx);

/// two_tables' Levels 1-3 (10 Level 3 tasks) written to `<fixture>/tasks.sqlite`; its path.
std::string two_tables_task_db(FixtureDataset& fx);

/// The first object of template `template_name`, or none.
graph::ObjectId object_of_template(const graph::SceneGraph& g, const std::string& template_name);
/// The first navigable platform owned by an object of template `owner_template`, or none.
graph::PlatformId navigable_platform_of(const graph::SceneGraph& g, const std::string& owner_template);

/// A room for render tests, in colour: a brown table_0 at the origin with a red cube, a tall green
/// box and a flat blue box on it; an empty grey table at x = 2.5; a "ghost" item on table_0 whose
/// mesh file is missing. Scene name "render_room".
BuiltScene render_room(FixtureDataset& fx);

}  // namespace mtg::testing
