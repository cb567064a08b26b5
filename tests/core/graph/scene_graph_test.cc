// Scene graph on small synthetic scenes the tests build themselves (OBJ boxes), with exact
// expected platforms, parents, regions and fits; plus the acceptance figures on the shipped data.

#include "core/graph/build.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/graph/free_space.h"
#include "core/graph/graph_json.h"
#include "core/scene/scene_loader.h"
#include "tests/support/fixture_dataset.h"
#include "tests/support/graph_fixtures.h"
#include "tests/support/shipped_data.h"

namespace mtg::graph {
namespace {

using ::testing::HasSubstr;
using testing::FixtureDataset;
using Box = FixtureDataset::Box;

constexpr double kTol = 1e-6;

using testing::add_table;
using testing::hab;

using Built = testing::BuiltScene;

Built build(const FixtureDataset& fx, const std::string& name) { return testing::build_fixture_scene(fx, name); }

const Platform& platform(const SceneGraph& g, const std::string& name) {
  const auto p = g.find_platform(name);
  EXPECT_TRUE(p.valid()) << name;
  return g.platforms.at(p);
}

const GraphObject& object(const SceneGraph& g, const std::string& name) {
  const auto o = g.find_object(name);
  EXPECT_TRUE(o.valid()) << name;
  return g.objects.at(o);
}

// Table with three 0.1 m boxes at x = -0.3, 0, 0.3, dropped from 1 cm above.
Built table_with_three_boxes(FixtureDataset& fx) {
  add_table(fx, "table");
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_scene("s", {{"object_instances",
                      {FixtureDataset::instance("toy_table", {0, 0, 0}),
                       FixtureDataset::instance("toy_box", hab(-0.3, 0, 0.75)),
                       FixtureDataset::instance("toy_box", hab(0.0, 0, 0.75)),
                       FixtureDataset::instance("toy_box", hab(0.3, 0, 0.75))}}});
  return build(fx, "s");
}

TEST(SceneGraph, TableWithThreeBoxesHasOneTopPlatformAndThreeChildren) {
  FixtureDataset fx;
  const Built b = table_with_three_boxes(fx);
  const SceneGraph& g = b.graph;
  ASSERT_EQ(g.platforms.size(), 1u);
  const Platform& top = g.platforms.front();
  EXPECT_EQ(top.name, "table_0_platform_0");
  EXPECT_NEAR(top.height, 0.74, kTol);
  EXPECT_NEAR(top.area(), 0.6, 1e-6);
  EXPECT_FALSE(top.interior);
  EXPECT_FALSE(std::isfinite(top.clearance));
  EXPECT_TRUE(top.destination);
  EXPECT_TRUE(top.navigable);
  EXPECT_EQ(top.label, 1);
  EXPECT_EQ(g.navigable, std::vector<PlatformId>{PlatformId(0)});
  for (const char* name : {"box_1", "box_2", "box_3"}) {
    const GraphObject& o = object(g, name);
    EXPECT_EQ(o.kind, ObjectKind::kItem) << name;
    EXPECT_EQ(o.parent, PlatformId(0)) << name;
    EXPECT_NEAR(o.bottom, 0.74, kTol) << name;   // settled down by 1 cm
    EXPECT_NEAR(o.settle_dz, -0.01, kTol) << name;
  }
  EXPECT_EQ(object(g, "table_0").kind, ObjectKind::kFurniture);
  EXPECT_EQ(g.pickable_on(PlatformId(0)).size(), 3u);
  for (const SideInfo& side : top.sides) {
    EXPECT_TRUE(side.usable());  // a free-standing table is reachable from every side
  }
  EXPECT_TRUE(g.warnings.empty()) << ::testing::PrintToString(g.warnings);
}

TEST(FreeSpace, RegionsExtendToTheNeighboursAndThePlatformEdge) {
  FixtureDataset fx;
  const SceneGraph g = table_with_three_boxes(fx).graph;
  const Platform& top = g.platforms.front();
  ASSERT_NEAR(top.X_WP.translation().norm(), 0.0, 1e-6);  // frame = world here (yaw 0)
  std::vector<geom::Ring> footprints;
  for (const graph::ObjectId o : top.items) footprints.push_back(g.objects[o].footprint);
  const auto obstacles = make_obstacles(top, top.items, footprints);
  const auto regions = object_regions(top, obstacles, 0.03);
  ASSERT_EQ(regions.size(), 24u);
  auto rect = [&](int object_k, int dir) { return regions[static_cast<size_t>(8 * object_k + dir)].rect_P; };
  auto expect_rect = [](const Eigen::AlignedBox2d& r, double x0, double y0, double x1, double y1) {
    EXPECT_NEAR(r.min().x(), x0, 1e-6);
    EXPECT_NEAR(r.min().y(), y0, 1e-6);
    EXPECT_NEAR(r.max().x(), x1, 1e-6);
    EXPECT_NEAR(r.max().y(), y1, 1e-6);
  };
  // Left box (x in [-0.35, -0.25]): its right region ends at the middle box.
  expect_rect(rect(0, 6), -0.25, -0.05, -0.05, 0.05);
  expect_rect(rect(0, 2), -0.5, -0.05, -0.35, 0.05);   // left: to the platform edge
  expect_rect(rect(0, 4), -0.35, 0.05, -0.25, 0.3);    // front
  expect_rect(rect(0, 0), -0.35, -0.3, -0.25, -0.05);  // rear
  // Front-right corner: nothing in that quadrant, so it runs to the platform's corner.
  expect_rect(rect(0, 5), -0.25, 0.05, 0.5, 0.3);
  // Middle box: both side regions end at the neighbours.
  expect_rect(rect(1, 2), -0.25, -0.05, -0.05, 0.05);
  expect_rect(rect(1, 6), 0.05, -0.05, 0.25, 0.05);
  for (const auto& r : regions) EXPECT_TRUE(r.numbered);
}

TEST(FreeSpace, FitsUseTheExactFeasibleSet) {
  FixtureDataset fx;
  const SceneGraph g = table_with_three_boxes(fx).graph;
  const Platform& top = g.platforms.front();
  std::vector<geom::Ring> footprints;
  for (const graph::ObjectId o : top.items) footprints.push_back(g.objects[o].footprint);
  const auto obstacles = make_obstacles(top, top.items, footprints);
  const auto regions = object_regions(top, obstacles, 0.03);
  const geom::Region gap = regions[6].region_P;  // right of the left box: 0.2 m wide
  auto square = [](double half) {
    return geom::Ring{{-half, -half}, {half, -half}, {half, half}, {-half, half}};
  };
  // 0.15 m fits between the boxes (centres x in [-0.175, -0.125]); 0.25 m does not.
  const geom::Region f15 = geom::intersect(feasible_positions(top, obstacles, square(0.075)), gap);
  ASSERT_FALSE(f15.empty());
  EXPECT_NEAR(geom::bounds(f15).min().x(), -0.175, 1e-6);
  EXPECT_NEAR(geom::bounds(f15).max().x(), -0.125, 1e-6);
  EXPECT_TRUE(geom::intersect(feasible_positions(top, obstacles, square(0.125)), gap).empty());
  // On the whole platform a 0.5 m square still fits only where the boxes leave room: nowhere
  // (the table is 0.6 deep and the boxes sit on its middle line).
  EXPECT_TRUE(feasible_positions(top, obstacles, square(0.25)).empty());
}

TEST(SceneGraph, ShelfWithTwoLayers) {
  FixtureDataset fx;
  // Boards 0.76 x 0.02 x 0.4: the lower one's surface at 0.32 m, the top's at 0.82 m; side
  // panels under the top board.
  fx.add_object_config("toy_shelf", fx.add_boxes_mesh("shelf", {{{0.76, 0.02, 0.4}, {0, 0.30, 0}},
                                                                {{0.84, 0.02, 0.4}, {0, 0.80, 0}},
                                                                {{0.02, 0.80, 0.4}, {-0.39, 0, 0}},
                                                                {{0.02, 0.80, 0.4}, {0.39, 0, 0}}}));
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  fx.add_scene("s", {{"object_instances", {FixtureDataset::instance("toy_shelf", {0, 0, 0}),
                                           FixtureDataset::instance("toy_box", hab(0.1, 0, 0.33))}}});
  const SceneGraph g = build(fx, "s").graph;
  ASSERT_EQ(g.platforms.size(), 2u);
  const Platform& low = platform(g, "shelf_0_platform_0");
  const Platform& high = platform(g, "shelf_0_platform_1");
  EXPECT_NEAR(low.height, 0.32, kTol);
  EXPECT_TRUE(low.interior);
  EXPECT_NEAR(low.clearance, 0.48, 1e-6);  // up to the top board's underside at 0.80
  EXPECT_NEAR(high.height, 0.82, kTol);
  EXPECT_FALSE(high.interior);
  EXPECT_EQ(object(g, "box_1").parent, g.find_platform("shelf_0_platform_0"));
  // The side panels hide the lower layer from the left and right; front and back are open.
  EXPECT_FALSE(low.sides[static_cast<size_t>(Side::kLeft)].usable());
  EXPECT_FALSE(low.sides[static_cast<size_t>(Side::kRight)].usable());
  EXPECT_TRUE(low.sides[static_cast<size_t>(Side::kFront)].usable());
  EXPECT_TRUE(low.navigable);
  EXPECT_EQ(low.label, 1);
  EXPECT_EQ(high.label, 2);
}

// A shelf whose lower layer is closed by doors on its left and right thirds, front and back (a
// TV stand): the platform is the part an arm reaches through the open middle (graph.md, "Reach"),
// its frame centred there; the same shelf without doors keeps its whole board, and so does the
// stand for tasks planned on whole surfaces (before mtg-tasks/5).
TEST(SceneGraph, ALayerBehindClosedDoorsIsOnlyThePartReachedThroughTheOpening) {
  FixtureDataset fx;
  const std::vector<Box> shelf = {
      {{0.76, 0.02, 0.4}, {0, 0.30, 0}}, {{0.84, 0.02, 0.4}, {0, 0.80, 0}},
      {{0.02, 0.80, 0.4}, {-0.39, 0, 0}}, {{0.02, 0.80, 0.4}, {0.39, 0, 0}}};
  auto with_doors = shelf;
  for (const double x : {-0.25, 0.25}) {
    for (const double z : {-0.21, 0.21}) with_doors.push_back({{0.26, 0.48, 0.02}, {x, 0.32, z}});
  }
  fx.add_object_config("toy_shelf", fx.add_boxes_mesh("shelf", shelf));
  fx.add_object_config("toy_stand", fx.add_boxes_mesh("stand", with_doors));
  fx.add_scene("open", {{"object_instances", {FixtureDataset::instance("toy_shelf", {0, 0, 0})}}});
  fx.add_scene("doors", {{"object_instances", {FixtureDataset::instance("toy_stand", {0, 0, 0})}}});
  const SceneGraph open = build(fx, "open").graph;
  const SceneGraph doors = build(fx, "doors").graph;
  const Platform& whole = platform(open, "shelf_0_platform_0");
  const Platform& reached = platform(doors, "stand_0_platform_0");
  EXPECT_NEAR(whole.area(), 0.76 * 0.4, 1e-3);
  ASSERT_TRUE(reached.navigable);
  EXPECT_LT(reached.area(), 0.5 * whole.area());
  EXPECT_GT(reached.area(), 0.2 * 0.4);  // at least the open middle, 24 cm wide, all the way back
  // Its frame is centred on what is reached: the middle of the shelf.
  EXPECT_NEAR(reached.X_WP.translation().norm(), 0.0, 0.02);
  EXPECT_NEAR(reached.box_P.center().norm(), 0.0, 1e-9);
  const geom::Region world = reached.polygon_W();
  EXPECT_TRUE(geom::contains(world, {0.0, 0.0}));
  EXPECT_TRUE(geom::contains(world, {0.0, 0.15}));
  for (const double x : {-0.33, 0.33}) {
    for (const double y : {-0.05, 0.0, 0.05}) {
      EXPECT_FALSE(geom::contains(world, {x, y})) << "behind a door at (" << x << ", " << y << ")";
    }
  }
  // The nine cells lie in the opening, none behind a door.
  for (const FreeRegion& cell : grid_cells(reached)) {
    const Eigen::Vector2d c = reached.X_WP * geom::centroid(cell.region_P);
    EXPECT_LT(std::abs(c.x()), 0.2) << "cell " << cell.dir;
  }
  const SceneGraph old = testing::build_fixture_scene(fx, "doors", PlatformRules::kWholeSurface).graph;
  const Platform& surface = platform(old, "stand_0_platform_0");
  EXPECT_NEAR(surface.area(), whole.area(), 1e-9);
  EXPECT_EQ(surface.X_WP.translation(), whole.X_WP.translation());
  EXPECT_TRUE(geom::contains(surface.polygon_W(), {0.33, 0.0}));
}

// An empty chair: from mtg-tasks/5 (PlatformRules::kReachedAndSeen) the robot arrives where it
// sees the seat, not behind the backrest; the release's rules leave an empty platform to the
// standing room, and here both sides have the same, so the first (the rear) wins: behind the
// backrest (graph.md, "The arrival side").
TEST(SceneGraph, AnEmptyChairIsSeenFromItsSeatsSideNotFromBehindItsBackrest) {
  FixtureDataset fx;
  // Boxes by size and bottom centre: a seat 45-49 cm up on four legs, a backrest 20 cm high
  // along its +z edge (the world's -y: the platform's rear).
  std::vector<Box> chair = {{{0.44, 0.04, 0.44}, {0, 0.45, 0}}, {{0.44, 0.2, 0.03}, {0, 0.49, 0.205}}};
  for (const double x : {-0.2, 0.2}) {
    for (const double z : {-0.2, 0.2}) chair.push_back({{0.03, 0.45, 0.03}, {x, 0.0, z}});
  }
  fx.add_object_config("toy_chair", fx.add_boxes_mesh("chair", chair));
  fx.add_scene("s", {{"object_instances", {FixtureDataset::instance("toy_chair", {0, 0, 0})}}});
  const SceneGraph seen = testing::build_fixture_scene(fx, "s", PlatformRules::kReachedAndSeen).graph;
  const SceneGraph release = testing::build_fixture_scene(fx, "s", PlatformRules::kWholeSurface).graph;
  const Platform& seat = platform(seen, "toy_chair_0_platform_0");
  ASSERT_TRUE(seat.navigable);
  ASSERT_TRUE(seat.items.empty());
  const auto& rear = seat.sides[static_cast<std::size_t>(Side::kRear)];
  ASSERT_TRUE(rear.usable());
  ASSERT_LT(rear.standing_point.y(), -0.3);  // behind the backrest
  ASSERT_GE(seat.default_side, 0);
  const auto& chosen = seat.sides[static_cast<std::size_t>(seat.default_side)];
  EXPECT_NE(seat.default_side, static_cast<int>(Side::kRear)) << "seen from behind its backrest";
  EXPECT_LT(rear.sight_lines, chosen.sight_lines);
  EXPECT_EQ(chosen.sight_lines, 9);  // every point of the seat in sight
  const Platform& old = platform(release, "toy_chair_0_platform_0");
  EXPECT_EQ(old.default_side, static_cast<int>(Side::kRear));
  EXPECT_EQ(old.sides[static_cast<std::size_t>(Side::kRear)].sight_lines, 0);  // not looked at
}

TEST(SceneGraph, EmptyPlatformGetsANineCellGrid) {
  FixtureDataset fx;
  add_table(fx, "table", 0.6, 0.9);
  fx.add_scene("s", {{"object_instances", {FixtureDataset::instance("toy_table", {0, 0, 0})}}});
  const SceneGraph g = build(fx, "s").graph;
  ASSERT_EQ(g.platforms.size(), 1u);
  const auto cells = grid_cells(g.platforms.front());
  for (const FreeRegion& c : cells) {
    EXPECT_NEAR(geom::area(c.region_P), 0.6 * 0.9 / 9.0, 1e-6) << direction_name(c.dir);
  }
  // Rear-left is the cell at minimum x and y of the platform frame; front is max y, middle x.
  EXPECT_NEAR(cells[1].rect_P.min().x(), g.platforms.front().box_P.min().x(), 1e-9);
  EXPECT_NEAR(cells[1].rect_P.min().y(), g.platforms.front().box_P.min().y(), 1e-9);
  EXPECT_NEAR(cells[4].rect_P.max().y(), g.platforms.front().box_P.max().y(), 1e-9);
  EXPECT_NEAR(cells[4].rect_P.center().x(), 0.0, 1e-9);
}

TEST(SceneGraph, AgentRelativeDirections) {
  // "front" is always the part farthest from the agent.
  EXPECT_EQ(platform_direction(4, Side::kRear), 4);
  EXPECT_EQ(platform_direction(4, Side::kFront), 0);
  EXPECT_EQ(platform_direction(4, Side::kLeft), 6);
  EXPECT_EQ(platform_direction(2, Side::kLeft), 4);  // looking along +x, left is +y
  EXPECT_EQ(platform_direction(kCentre, Side::kRight), kCentre);
  for (int d = 0; d < 8; ++d) {
    for (const Side s : kSides) EXPECT_EQ(relative_direction(platform_direction(d, s), s), d);
  }
}

TEST(SceneGraph, ItemAcrossTwoSupportsRestsOnTheLargerOne) {
  FixtureDataset fx;
  add_table(fx, "table");
  fx.add_object_config("toy_book", fx.add_box_mesh("book", {0.2, 0.03, 0.2}));
  fx.add_object_config("toy_plank", fx.add_box_mesh("plank", {0.3, 0.02, 0.1}));
  // Two books side by side; a plank lies across both, 60 % over the second.
  fx.add_scene("s", {{"object_instances", {FixtureDataset::instance("toy_table", {0, 0, 0}),
                                           FixtureDataset::instance("toy_book", hab(-0.1, 0, 0.74)),
                                           FixtureDataset::instance("toy_book", hab(0.1, 0, 0.74)),
                                           FixtureDataset::instance("toy_plank", hab(0.03, 0, 0.77))}}});
  const SceneGraph g = build(fx, "s").graph;
  const GraphObject& plank = object(g, "plank_3");
  ASSERT_TRUE(plank.parent.valid());
  EXPECT_EQ(g.platforms[plank.parent].owner, g.find_object("book_2"));
  EXPECT_NEAR(plank.bottom, 0.77, kTol);
}

TEST(SceneGraph, BadInputWarnsAndTheRestStillBuilds) {
  FixtureDataset fx;
  add_table(fx, "table");
  fx.add_object_config("toy_box", fx.add_box_mesh("box", {0.1, 0.1, 0.1}));
  // A degenerate mesh: every triangle has zero area.
  fx.add_raw_file("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  fx.add_object_config("toy_flat", "../../objects/flat.obj");
  nlohmann::json zero;
  zero["user_defined"]["receptacle_aabb_none"] = {{"position", {0, 0.75, 0}}, {"scale", {0, 0.1, 0}}};
  fx.add_object_config("toy_desk", fx.add_boxes_mesh("desk", {{{1.0, 0.04, 0.6}, {0, 0.70, 0}},
                                                              {{0.04, 0.7, 0.04}, {0, 0, 0}}}), zero);
  fx.add_scene("s", {{"object_instances",
                      {FixtureDataset::instance("toy_table", {0, 0, 0}),
                       FixtureDataset::instance("toy_box", hab(5, 5, 1.5)),  // floats over nothing
                       FixtureDataset::instance("toy_flat", hab(0, 0, 0.74)),
                       FixtureDataset::instance("toy_desk", hab(3, 0, 0)),
                       FixtureDataset::instance("toy_box", hab(0, 0, 0.74))}}});
  const Built b = build(fx, "s");
  const SceneGraph& g = b.graph;
  const std::string all = ::testing::PrintToString(g.warnings);
  EXPECT_THAT(all, HasSubstr("object box_1 cannot be placed"));
  EXPECT_THAT(all, HasSubstr("receptacle receptacle_aabb_none of desk_3 has zero area"));
  EXPECT_EQ(object(g, "box_1").kind, ObjectKind::kUnsupported);
  EXPECT_EQ(object(g, "box_4").kind, ObjectKind::kItem);  // the rest still builds
  EXPECT_EQ(object(g, "box_4").parent, g.find_platform("table_0_platform_0"));
  EXPECT_EQ(object(g, "flat_2").kind, ObjectKind::kUnsupported);
  EXPECT_THAT(all, HasSubstr("flat_2"));
}

TEST(SceneGraph, GraphJsonHasTheDocumentedFields) {
  FixtureDataset fx;
  const Built b = table_with_three_boxes(fx);
  const nlohmann::json j = graph_to_json(b.graph, GraphOptions{});
  EXPECT_EQ(j["scene"], "s");
  ASSERT_EQ(j["platforms"].size(), 1u);
  const auto& p = j["platforms"][0];
  for (const char* key : {"name", "owner", "height", "navigable", "polygon", "items"}) {
    EXPECT_TRUE(p.contains(key)) << key;
  }
  EXPECT_EQ(p["items"].size(), 3u);
  EXPECT_EQ(p["label"], "l1");
  for (const auto& o : j["objects"]) {
    for (const char* key : {"name", "kind", "parent", "footprint"}) EXPECT_TRUE(o.contains(key)) << key;
  }
  EXPECT_EQ(j["objects"][0]["parent"], "ground");
  EXPECT_EQ(j["objects"][1]["parent"], "table_0_platform_0");
}

}  // namespace
}  // namespace mtg::graph
