// What the agent can see (id_raster.h, visibility.h): the id pass keeps the nearer surface and
// counts silhouettes; an object behind a taller one is not clearly visible and no task names it;
// the oracle's windows (scenery drawn once, only the deciding items per state) answer exactly as
// whole passes of the same view, in every state tried, on a fixture and on a shipped apartment.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <set>

#include "core/episode/rules.h"
#include "core/render/id_raster.h"
#include "core/render/view.h"
#include "core/render/visibility.h"
#include "core/tasks/generator.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/shipped_data.h"
#include "tests/support/shipped_scene.h"
#include "core/graph/build.h"
#include "core/scene/scene_loader.h"

namespace mtg::render {
namespace {

// A table seen from its arrival side: a 30 cm tower right in front of a 6 cm cube, and a lone
// box at the side. Scene "hidden".
testing::BuiltScene hidden_behind_a_tower(testing::FixtureDataset& fx) {
  testing::add_table(fx, "table", 1.0, 0.6);
  fx.add_object_config("toy_tower", fx.add_box_mesh("tower", {0.14, 0.30, 0.14}));
  fx.add_object_config("toy_cube", fx.add_box_mesh("cube", {0.06, 0.06, 0.06}));
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_scene("hidden", {{"object_instances",
                           {testing::FixtureDataset::instance("toy_table", {0, 0, 0}),
                            testing::FixtureDataset::instance("toy_tower", testing::hab(0.0, -0.12, 0.75)),
                            testing::FixtureDataset::instance("toy_cube", testing::hab(0.0, 0.12, 0.75)),
                            testing::FixtureDataset::instance("toy_box", testing::hab(0.35, 0.0, 0.75)),
                            testing::FixtureDataset::instance("toy_table", testing::hab(3, 0, 0))}}});
  return testing::build_fixture_scene(fx, "hidden");
}

TEST(IdPass, KeepsTheNearerSurfaceAndCountsSilhouettesWhateverIsInFront) {
  ObjectTriangles square;  // a 1 m square in the object's xz plane, facing -y
  square.vertices_O = {{-0.5f, 0, -0.5f}, {0.5f, 0, -0.5f}, {0.5f, 0, 0.5f}, {-0.5f, 0, 0.5f}};
  square.indices = {0, 1, 2, 0, 2, 3};
  Camera cam;
  cam.width = 64;
  cam.height = 48;
  cam.fovy = 1.0;
  cam.X_WC = look_at({0, -3, 0}, {0, 0, 0});
  IdPass pass(cam);
  const Eigen::Isometry3d far(Eigen::Translation3d(0, 1, 0)), near(Eigen::Translation3d(0.3, 0, 0));
  const int far_alone = pass.draw(square, far, 1);
  const int near_alone = pass.draw(square, near, 2);
  EXPECT_GT(far_alone, 50);
  EXPECT_GT(near_alone, far_alone) << "the nearer square looks bigger";
  int ones = 0, twos = 0;
  for (const std::int32_t id : pass.image().ids) (id == 1 ? ones : id == 2 ? twos : ones) += id > 0 ? 1 : 0;
  EXPECT_EQ(twos, near_alone) << "nothing covers the near square";
  EXPECT_LT(ones, far_alone) << "the near square covers part of the far one";
  // Drawn in the other order, the same pixels.
  IdPass other(cam);
  other.draw(square, near, 2);
  other.draw(square, far, 1);
  EXPECT_EQ(other.image().ids, pass.image().ids);
  // A window of a pass holds exactly the whole pass's pixels there.
  IdPass window(cam, IdImage(10, 8, 30, 20));
  window.draw(square, far, 1);
  window.draw(square, near, 2);
  for (int v = 0; v < 20; ++v) {
    for (int u = 0; u < 30; ++u) ASSERT_EQ(window.image().at(u, v), pass.image().at(u + 10, v + 8));
  }
}

// A box of `size` about its centre: front and back faces overlap in every view.
ObjectTriangles box_triangles(const Eigen::Vector3f& size) {
  ObjectTriangles box;
  for (int k = 0; k < 8; ++k) {
    box.vertices_O.emplace_back((k & 1 ? 0.5f : -0.5f) * size.x(), (k & 2 ? 0.5f : -0.5f) * size.y(),
                                (k & 4 ? 0.5f : -0.5f) * size.z());
  }
  box.indices = {0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 3, 7, 1, 7, 5};
  return box;
}

TEST(IdPass, ASplatDrawsTheSamePixelsAndSilhouetteAsItsTriangles) {
  Camera cam;
  cam.width = 64;
  cam.height = 48;
  cam.fovy = 1.0;
  cam.X_WC = look_at({0, -3, 0}, {0, 0, 0});
  const ObjectTriangles box = box_triangles({0.8f, 0.6f, 0.7f});
  // A box behind, one in front of it, one at the same place (equal depths: the first drawn keeps
  // its pixels), one half out of the picture, one through the near plane, one out of sight.
  const std::vector<Eigen::Isometry3d> poses = {
      Eigen::Isometry3d(Eigen::Translation3d(0.1, 1.0, 0.05)), Eigen::Isometry3d(Eigen::Translation3d(0.3, 0.0, -0.2)),
      Eigen::Isometry3d(Eigen::Translation3d(0.3, 0.0, -0.2)), Eigen::Isometry3d(Eigen::Translation3d(1.6, 0.5, 0.9)),
      Eigen::Isometry3d(Eigen::Translation3d(0.2, -2.9, 0.1)), Eigen::Isometry3d(Eigen::Translation3d(0.0, -6.0, 0.0))};
  // The whole image, and windows whose rows end off the four-pixel step.
  for (const IdImage& start : {IdImage(64, 48), IdImage(10, 8, 30, 21), IdImage(3, 0, 61, 47)}) {
    IdPass drawn(cam, start);
    drawn.draw(box, Eigen::Isometry3d(Eigen::Translation3d(-0.4, 1.5, 0.0)), 99);  // scenery behind
    IdImage pasted = drawn.image();
    for (std::size_t k = 0; k < poses.size(); ++k) {
      const auto id = static_cast<std::int32_t>(k + 1);
      const int by_triangles = drawn.draw(box, poses[k], id);
      const int by_splat = composite(splat_of(cam, box, poses[k]), id, pasted);
      EXPECT_EQ(by_splat, by_triangles) << "box " << k << " in window " << start.left << "," << start.top;
      if (k == 2) {
        EXPECT_GT(std::count(pasted.ids.begin(), pasted.ids.end(), 2), 0) << "the front box shows";
        EXPECT_EQ(std::count(pasted.ids.begin(), pasted.ids.end(), 3), 0) << "its twin drawn after it does not";
      }
    }
    EXPECT_EQ(pasted.ids, drawn.image().ids);
    ASSERT_EQ(pasted.depth.size(), drawn.image().depth.size());
    EXPECT_EQ(std::memcmp(pasted.depth.data(), drawn.image().depth.data(), pasted.depth.size() * sizeof(float)), 0);
  }
  EXPECT_TRUE(splat_of(cam, box, poses[5]).runs.empty()) << "out of sight: nothing";
  EXPECT_FALSE(splat_of(cam, box, poses[4]).runs.empty()) << "through the near plane: what lies in front";
}

TEST(Visibility, AnObjectBehindATallerOneIsNotClearlyVisibleAndNoTaskNamesIt) {
  testing::FixtureDataset fx;
  auto b = hidden_behind_a_tower(fx);
  // The graph arrives where the view shows most: not at the rear, where the tower hides the cube.
  const graph::PlatformId table = b.graph.navigable[0];
  ASSERT_TRUE(b.graph.platforms[table].sides[0].usable());
  EXPECT_NE(b.graph.platforms[table].default_side, 0);
  EXPECT_LT(b.graph.platforms[table].sides[0].objects_seen,
            b.graph.platforms[table].sides[static_cast<std::size_t>(b.graph.platforms[table].default_side)].objects_seen);
  {
    const SceneGeometry geometry(b.scene, b.graph);
    const VisibilityOracle oracle(b.graph, geometry);
    const graph::ObjectId cube = testing::object_of_template(b.graph, "toy_cube");
    EXPECT_TRUE(oracle.arrival_view(episode::initial_state(b.graph), table)->clearly_visible(cube));
  }
  // Made to arrive at the rear (as a scene with a wall on the other sides would), the cube is hidden.
  b.graph.platforms[table].default_side = 0;
  const graph::SceneGraph& g = b.graph;
  const SceneGeometry geometry(b.scene, g);
  const VisibilityOracle oracle(g, geometry);
  const episode::WorldState s = episode::initial_state(g);
  const auto sight = oracle.arrival_view(s, table);
  const graph::ObjectId tower = testing::object_of_template(g, "toy_tower");
  const graph::ObjectId cube = testing::object_of_template(g, "toy_cube");
  const graph::ObjectId box = testing::object_of_template(g, "toy_box");
  EXPECT_TRUE(sight->clearly_visible(tower));
  EXPECT_TRUE(sight->clearly_visible(box));
  EXPECT_FALSE(sight->clearly_visible(cube)) << sight->of(cube).visible << " of " << sight->of(cube).silhouette;
  EXPECT_LT(sight->of(cube).share(), oracle.options().min_share);
  // With the tower in hand, the cube shows.
  episode::WorldState held = s;
  episode::pick(g, held, tower);
  EXPECT_TRUE(oracle.arrival_view(held, table)->clearly_visible(cube));

  tasks::TaskOptions options;
  options.levels = {1, 2, 3};
  options.level3_count = 50;
  const auto r = tasks::generate_tasks(b.scene, g, options);
  EXPECT_GT(r.set.dropped.by_reason.at("occluded").at(1), 0);
  int naming_the_tower = 0;
  for (const tasks::Task& t : r.set.tasks) {
    if (t.level < 3) {
      EXPECT_NE(t.item, g.objects[cube].name) << t.text;
    }
    naming_the_tower += t.item == g.objects[tower].name ? 1 : 0;
  }
  EXPECT_GT(naming_the_tower, 0);
  // Without the visibility rules the cube is named.
  options.visibility.reset();
  const auto blind = tasks::generate_tasks(b.scene, g, options);
  EXPECT_TRUE(std::any_of(blind.set.tasks.begin(), blind.set.tasks.end(),
                          [&](const tasks::Task& t) { return t.item == g.objects[cube].name; }));
}

// The oracle against whole passes of the same view, object by object, in `states`.
void expect_windows_answer_as_whole_passes(const graph::SceneGraph& g, const SceneGeometry& geometry,
                                           const std::vector<episode::WorldState>& states) {
  const VisibilityOracle oracle(g, geometry);
  const VisibilityOptions& vo = oracle.options();
  int compared = 0;
  for (const episode::WorldState& s : states) {
    for (const graph::PlatformId p : g.navigable) {
      const int side = std::max(0, g.platforms[p].default_side);
      const auto pictures = platform_pictures(g, s, p, side, vo.image_width, vo.image_height);
      const auto windowed = oracle.arrival_view(s, p);
      ASSERT_EQ(windowed->pictures(), pictures.size()) << g.platforms[p].name;
      for (std::size_t k = 0; k < pictures.size(); ++k) {
        const Camera& camera = pictures[k].camera;
        const IdView whole = draw_id_view(g, geometry, s, at_resolution(camera, vo.pass_width(), vo.pass_height()));
        const ViewSight whole_sight(camera, whole.objects, vo);
        for (const graph::ObjectId o : episode::everything_on(g, s, p)) {
          if (o == s.held) continue;
          ASSERT_EQ(windowed->of(k, o).visible, whole_sight.of(o).visible)
              << g.objects[o].name << " on " << g.platforms[p].name << ", picture " << k;
          ASSERT_EQ(windowed->of(k, o).silhouette, whole_sight.of(o).silhouette) << g.objects[o].name << ", picture " << k;
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 10);
}

TEST(Visibility, TheOraclesWindowsAnswerAsWholePassesDo) {
  testing::FixtureDataset fx;
  const auto b = hidden_behind_a_tower(fx);
  const graph::SceneGraph& g = b.graph;
  const SceneGeometry geometry(b.scene, g);
  std::vector<episode::WorldState> states = {episode::initial_state(g)};
  // The tower in hand; the tower moved to the other table; the box moved behind the tower.
  episode::RuleOptions rules;
  for (const std::vector<std::string>& keys :
       {std::vector<std::string>{"l1", "o1"}, {"l1", "o1", "l2", "startplace", "5"}, {"l1", "o3", "l1", "startplace", "999"}}) {
    episode::WorldState s = episode::initial_state(g);
    for (const std::string& k : keys) episode::apply_action(g, s, k, {}, rules);
    states.push_back(s);
  }
  expect_windows_answer_as_whole_passes(g, geometry, states);
}

TEST(Visibility, OnAShippedApartmentTheWindowsAnswerAsWholePassesDo) {
  MTG_REQUIRE_SHIPPED_DATA();
  const testing::ShippedScene shipped = testing::load_shipped_scene("apt_0");
  const scene::Scene& s = shipped.scene;
  const graph::SceneGraph& g = shipped.graph;
  const SceneGeometry geometry(s, g);
  std::vector<episode::WorldState> states = {episode::initial_state(g)};
  // Every item of the busiest platform picked in turn (each leaves the view and the numbering).
  const graph::PlatformId busiest = *std::max_element(g.navigable.begin(), g.navigable.end(), [&](auto a, auto b) {
    return episode::pickable_on(g, states[0], a).size() < episode::pickable_on(g, states[0], b).size();
  });
  for (const graph::ObjectId o : episode::pickable_on(g, states[0], busiest)) {
    episode::WorldState held = states[0];
    episode::pick(g, held, o);
    states.push_back(held);
    if (states.size() > 8) break;
  }
  expect_windows_answer_as_whole_passes(g, geometry, states);
}

// A held object's close-up shows what it carries: picked, a spice rack keeps its jars and a
// plate its cup (world_state.h, pick), so the item view draws them too, all in the frame. A
// rater saw a held rack drawn empty though it arrived full. And the platform it came from shows
// none of it: a rater saw a held rack's eight jars floating over the counter, unnumbered.
TEST(ItemView, AHeldObjectIsShownWithWhatItCarries) {
  MTG_REQUIRE_SHIPPED_DATA();
  const testing::ShippedScene shipped = testing::load_shipped_scene("apt_0");
  const graph::SceneGraph& g = shipped.graph;
  const episode::WorldState start = episode::initial_state(g);
  const SceneGeometry geometry(shipped.scene, g);
  int carriers = 0;
  for (const graph::ObjectId o : g.objects.ids()) {
    if (!g.objects[o].pickable()) continue;
    std::vector<graph::ObjectId> carried;
    for (const graph::PlatformId p : g.objects[o].platforms) {
      for (const graph::ObjectId c : episode::everything_on(g, start, p)) carried.push_back(c);
    }
    if (carried.empty()) continue;
    ++carriers;
    episode::WorldState held = start;
    episode::pick(g, held, o);
    ViewRequest r;
    r.view = ViewKind::kItem;
    r.object = o;
    const ViewPlan plan = plan_view(g, held, r);
    EXPECT_EQ(plan.only, o);
    EXPECT_EQ(std::set<graph::ObjectId>(plan.only_with.begin(), plan.only_with.end()),
              std::set<graph::ObjectId>(carried.begin(), carried.end()))
        << g.objects[o].name;
    // Where it stood: the platform view hides all of it, and the id pass the generator counts
    // from draws none of it.
    const graph::PlatformId from = episode::furniture_platform_of(g, start, o);
    ViewRequest at;
    at.platform = from;
    at.marks = MarkKind::kItems;
    held.at_platform = from;
    held.side = std::max(0, g.platforms[from].default_side);
    held.phase = episode::Phase::kAtPlatform;
    const ViewPlan there = plan_view(g, held, at);
    const std::set<graph::ObjectId> hidden(there.hidden.begin(), there.hidden.end());
    const IdView ids = draw_id_view(g, geometry, held, at_resolution(there.camera, 160, 120));
    EXPECT_EQ(hidden.count(o), 1u) << g.objects[o].name;
    for (const graph::ObjectId c : carried) {
      EXPECT_EQ(hidden.count(c), 1u) << g.objects[c].name << " on the held " << g.objects[o].name;
      EXPECT_TRUE(std::none_of(ids.objects.begin(), ids.objects.end(),
                               [&](const ObjectSight& sight) { return sight.object == static_cast<std::int32_t>(c.index()); }))
          << g.objects[c].name << " drawn where the held " << g.objects[o].name << " stood";
    }
    for (const graph::ObjectId c : carried) {
      const episode::ObjectState& cs = held.objects[c];
      const geom::Point2 xy = episode::footprint_centre(cs);
      const auto px = plan.camera.project(Eigen::Vector3d(xy.x(), xy.y(), cs.top));
      ASSERT_TRUE(px.has_value()) << g.objects[c].name << " on " << g.objects[o].name;
      EXPECT_TRUE(px->x() >= 0 && px->x() < r.width && px->y() >= 0 && px->y() < r.height)
          << g.objects[c].name << " on " << g.objects[o].name << " at " << px->transpose();
    }
  }
  EXPECT_GE(carriers, 3) << "apt_0 has a spice rack with jars, a plate with a cup and books on books";
}

}  // namespace
}  // namespace mtg::render
