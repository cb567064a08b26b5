// The renderer on real geometry: golden images of a small coloured fixture room and of an apt_0
// shelf, numbers that are the action space's keys and sit on their items, the picked item gone
// and the placed one drawn, and clear errors for bad requests after which rendering goes on.
// These tests need a headless GL context (Mesa's llvmpipe is enough).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/episode/rules.h"
#include "core/episode/state_delta.h"
#include "core/render/image_codec.h"
#include "core/render/image_renderer.h"
#include "core/render/mark_layout.h"
#include "core/render/target_layout.h"
#include "core/render/view.h"
#include "core/render/visibility.h"
#include "core/util/error.h"
#include "tests/support/golden_image.h"
#include "tests/support/graph_fixtures.h"
#include "core/render/overlay.h"
#include "tests/support/shipped_data.h"
#include "tests/support/shipped_scene.h"

namespace mtg {
namespace {

using ::testing::HasSubstr;

graph::ObjectId object_of(const graph::SceneGraph& g, const std::string& template_name) {
  const graph::ObjectId i = testing::object_of_template(g, template_name);
  if (!i.valid()) ADD_FAILURE() << "no object of template " << template_name;
  return i;
}

graph::PlatformId top_of(const graph::SceneGraph& g, const std::string& owner_template) {
  const graph::PlatformId p = testing::navigable_platform_of(g, owner_template);
  if (!p.valid()) ADD_FAILURE() << "no navigable platform on " << owner_template;
  return p;
}

cv::Mat decode(const render::EncodedImage& e) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(e.bytes.size()), CV_8UC1, const_cast<std::uint8_t*>(e.bytes.data())),
                      cv::IMREAD_COLOR);
}

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fx_ = new testing::FixtureDataset();
    built_ = new testing::BuiltScene(testing::render_room(*fx_));
    renderer_ = new render::ImageRenderer("none");
  }
  static void TearDownTestSuite() {
    delete renderer_;
    delete built_;
    delete fx_;
  }

  const graph::SceneGraph& g() const { return built_->graph; }
  graph::PlatformId table() const { return top_of(g(), "toy_wood_table"); }
  graph::PlatformId empty_table() const { return top_of(g(), "toy_grey_table"); }

  // The robot at `platform` on its default side, hands empty.
  episode::WorldState at(graph::PlatformId platform) const {
    episode::WorldState s = episode::initial_state(g());
    s.phase = episode::Phase::kAtPlatform;
    s.at_platform = platform;
    s.side = g().platforms[platform].default_side;
    return s;
  }

  render::ImageRequest request(const episode::WorldState& s, std::vector<render::ViewSpec> views) const {
    render::ImageRequest r;
    r.scene = "render_room";
    r.data_dir = fx_->root().string();
    r.state = episode::state_delta(g(), s);
    r.views = std::move(views);
    return r;
  }

  render::ViewSpec platform_view(graph::PlatformId p, render::MarkKind marks) const {
    return {render::ViewKind::kPlatform, g().platforms[p].name, -1, "", marks, 0, ""};
  }

  // Renders a plan with the renderer's GPU copy of the fixture.
  render::ViewImages draw(const episode::WorldState& s, const render::ViewPlan& plan, bool marks = false) {
    const auto& entry = renderer_->scenes().load("render_room", fx_->root().string());
    return render::draw_view(renderer_->scene_renderer(entry), entry.graph, s, plan, marks, renderer_->geometry(entry));
  }

  static testing::FixtureDataset* fx_;
  static testing::BuiltScene* built_;
  static render::ImageRenderer* renderer_;
};

testing::FixtureDataset* RenderTest::fx_ = nullptr;
testing::BuiltScene* RenderTest::built_ = nullptr;
render::ImageRenderer* RenderTest::renderer_ = nullptr;

TEST_F(RenderTest, FixtureViewsMatchTheirGoldenImages) {
  episode::WorldState s = at(table());
  auto reply = renderer_->render(request(s, {platform_view(table(), render::MarkKind::kItems)}));
  ASSERT_EQ(reply.images.size(), 2u);
  EXPECT_EQ(reply.images[0].role, "view");
  EXPECT_EQ(reply.images[1].role, "view_marked");
  EXPECT_EQ(testing::compare_golden_image("render/room_table.png", decode(reply.images[0])), "");
  EXPECT_EQ(testing::compare_golden_image("render/room_table_marked.png", decode(reply.images[1])), "");

  // Holding the red cube at the empty table, about to place: the 3x3 grid numbered as its keys.
  episode::pick(g(), s, object_of(g(), "toy_red_cube"));
  s.at_platform = empty_table();
  s.side = g().platforms[empty_table()].default_side;
  s.phase = episode::Phase::kPlacing;
  reply = renderer_->render(request(s, {platform_view(empty_table(), render::MarkKind::kTargets),
                                        {render::ViewKind::kItem, "", -1, g().objects[s.held].name,
                                         render::MarkKind::kNone, 0, ""},
                                        {render::ViewKind::kTopdown, "", -1, "", render::MarkKind::kLabels, 0, ""}}));
  ASSERT_EQ(reply.images.size(), 5u);
  EXPECT_EQ(reply.images[2].role, "item");
  EXPECT_EQ(reply.images[4].role, "topdown_marked");
  EXPECT_EQ(testing::compare_golden_image("render/room_grid_marked.png", decode(reply.images[1])), "");
  EXPECT_EQ(testing::compare_golden_image("render/room_held_item.png", decode(reply.images[2])), "");
  EXPECT_EQ(testing::compare_golden_image("render/room_topdown_marked.png", decode(reply.images[4])), "");
}

// The CPU id pass draws what the GL renderer draws: where GL shows the background, the id pass
// shows nothing, and elsewhere an object, for all but a sliver of edge pixels.
TEST_F(RenderTest, TheCpuIdPassCoversWhatGlDraws) {
  const episode::WorldState s = at(table());
  const auto& entry = renderer_->scenes().load("render_room", fx_->root().string());
  render::ViewRequest r;
  r.platform = table();
  const render::ViewPlan plan = render::plan_view(g(), s, r);
  const render::ViewImages gl = draw(s, plan);
  const render::IdImage ids =
      render::draw_id_view(g(), renderer_->geometry(entry), s, plan.camera, plan.hidden).image;
  const cv::Vec3b background(235, 222, 214);
  int agree = 0, objects = 0;
  for (int v = 0; v < gl.plain.rows; ++v) {
    for (int u = 0; u < gl.plain.cols; ++u) {
      const bool gl_empty = gl.plain.at<cv::Vec3b>(v, u) == background;
      const bool cpu_empty = ids.at(u, v) == render::IdImage::kNone;
      agree += gl_empty == cpu_empty ? 1 : 0;
      objects += cpu_empty ? 0 : 1;
    }
  }
  const double share = static_cast<double>(agree) / (gl.plain.rows * gl.plain.cols);
  EXPECT_GT(share, 0.995) << "GL and the id pass disagree on " << 100 * (1 - share) << " % of the pixels";
  EXPECT_GT(objects, 640 * 480 / 10) << "the view shows its table";
}

TEST_F(RenderTest, ItemAndTargetNumbersAreTheActionSpaceKeys) {
  episode::WorldState s = at(table());
  const episode::RuleOptions rules;
  std::vector<std::string> item_keys;
  for (const auto& a : episode::action_space(g(), s, rules)) {
    if (a.key[0] == 'o') item_keys.push_back(a.key);
  }
  const auto items = render::item_marks(g(), s, table());
  ASSERT_EQ(items.size(), item_keys.size());
  ASSERT_EQ(items.size(), 3u) << "the ghost has no geometry, so it is not an item";
  for (std::size_t k = 0; k < items.size(); ++k) {
    EXPECT_EQ("o" + std::to_string(items[k].number), item_keys[k]);
    EXPECT_EQ(items[k].object, episode::pickable_on(g(), s, table())[k]);
  }

  episode::pick(g(), s, items[0].object);
  s.phase = episode::Phase::kPlacing;
  std::vector<std::string> place_keys;
  for (const auto& a : episode::action_space(g(), s, rules)) {
    if (a.key != "0" && a.key != episode::kAnywhereKey) place_keys.push_back(a.key);
  }
  const auto regions = render::target_marks(g(), s, table(), static_cast<graph::Side>(s.side), rules.min_region_size);
  ASSERT_FALSE(regions.empty());
  ASSERT_EQ(regions.size(), place_keys.size());
  for (std::size_t k = 0; k < regions.size(); ++k) EXPECT_EQ(std::to_string(regions[k].number), place_keys[k]);

  // Set down again, the item takes a new number and number 1 stays retired (stable numbering):
  // the marks are still exactly the keys offered.
  ASSERT_TRUE(episode::apply_action(g(), s, episode::kAnywhereKey, {}, rules).applied);
  std::vector<std::string> keys_after;
  for (const auto& a : episode::action_space(g(), s, rules)) {
    if (a.key[0] == 'o') keys_after.push_back(a.key);
  }
  std::vector<std::string> marks_after;
  for (const render::ItemMark& m : render::item_marks(g(), s, table())) marks_after.push_back("o" + std::to_string(m.number));
  EXPECT_EQ(marks_after, keys_after);
  EXPECT_EQ(marks_after, (std::vector<std::string>{"o2", "o3", "o4"}));
}

TEST_F(RenderTest, EachNumberSitsOnItsItem) {
  const episode::WorldState s = at(table());
  render::ViewRequest r;
  r.platform = table();
  r.marks = render::MarkKind::kItems;
  const render::ViewPlan plan = render::plan_view(g(), s, r);
  ASSERT_EQ(plan.marks.items.size(), 3u);
  const cv::Vec3b background(235, 222, 214);
  for (const render::ItemMark& m : plan.marks.items) {
    render::ViewPlan alone = plan;
    alone.only = m.object;  // the item by itself, seen by the same camera
    const cv::Mat image = draw(s, alone).plain;
    const auto px = plan.camera.project(m.anchor_W - Eigen::Vector3d(0, 0, 0.01));
    ASSERT_TRUE(px.has_value());
    const cv::Point p(static_cast<int>(px->x()), static_cast<int>(px->y()));
    ASSERT_TRUE(cv::Rect(0, 0, image.cols, image.rows).contains(p));
    EXPECT_NE(image.at<cv::Vec3b>(p), background) << "mark " << m.number << " is not on " << g().objects[m.object].name;
  }
}

// A close-up of one item where it stands: every other item faded to 20 % (the view with them
// over the view without them), the item itself and the furniture untouched.
TEST_F(RenderTest, AFocusCloseUpFadesEveryOtherItem) {
  const episode::WorldState s = episode::initial_state(g());
  const graph::ObjectId cube = object_of(g(), "toy_red_cube");
  render::ViewRequest r;
  r.view = render::ViewKind::kFocus;
  r.object = cube;
  const render::ViewPlan focus = render::plan_view(g(), s, r);
  const graph::ObjectId tower = object_of(g(), "toy_green_tower"), slab = object_of(g(), "toy_blue_slab");
  EXPECT_THAT(focus.faded, ::testing::Contains(tower));
  EXPECT_THAT(focus.faded, ::testing::Contains(slab));
  EXPECT_THAT(focus.faded, ::testing::Not(::testing::Contains(cube)));
  EXPECT_THAT(focus.faded, ::testing::Not(::testing::Contains(object_of(g(), "toy_wood_table"))));
  render::ViewPlan solid = focus, without = focus;
  solid.faded.clear();
  without.faded.clear();
  without.hidden = focus.faded;
  const cv::Mat shown = draw(s, focus).plain, all = draw(s, solid).plain, none = draw(s, without).plain;
  cv::Mat expected;
  cv::addWeighted(all, render::kFadedVisibility, none, 1.0 - render::kFadedVisibility, 0.0, expected);
  cv::Mat diff;
  cv::absdiff(shown, expected, diff);
  double worst = 0.0;
  cv::minMaxLoc(diff.reshape(1), nullptr, &worst);
  EXPECT_LE(worst, 1.0);
  // The cube is in the middle of the picture and solid red.
  const auto px = focus.camera.project(s.objects[cube].position);
  ASSERT_TRUE(px.has_value());
  EXPECT_NEAR(px->x(), focus.camera.width / 2.0, focus.camera.width / 4.0);
  const cv::Vec3b red = shown.at<cv::Vec3b>(cv::Point(static_cast<int>(px->x()), static_cast<int>(px->y())));
  EXPECT_GT(red[2], 2 * red[1]);
}

TEST_F(RenderTest, APickedItemVanishesAndAPlacedItemAppearsWhereTheStateSays) {
  episode::WorldState s = at(table());
  render::ViewRequest r;
  r.platform = table();
  r.marks = render::MarkKind::kItems;
  const render::ViewPlan before = render::plan_view(g(), s, r);
  const graph::ObjectId cube = object_of(g(), "toy_red_cube");
  const auto cube_px = before.camera.project(episode::initial_state(g()).objects[cube].position);
  ASSERT_TRUE(cube_px.has_value());
  const cv::Point p(static_cast<int>(cube_px->x()), static_cast<int>(cube_px->y()));
  const cv::Vec3b red_before = draw(s, before).plain.at<cv::Vec3b>(p);
  EXPECT_GT(red_before[2], 2 * red_before[1]) << "the cube is red where it stands";

  episode::pick(g(), s, cube);
  const render::ViewPlan after = render::plan_view(g(), s, r);
  EXPECT_EQ(after.marks.items.size(), 2u) << "numbers shift once the cube is in hand";
  const cv::Vec3b there_after = draw(s, after).plain.at<cv::Vec3b>(p);
  EXPECT_LT(there_after[2], 2 * there_after[1]) << "the cube is gone from the table";

  // Put it on the empty table's centre and look there.
  s.at_platform = empty_table();
  s.side = g().platforms[empty_table()].default_side;
  const Eigen::Vector2d centre = episode::platform_frame(g(), s, empty_table()).translation();
  episode::place_held(g(), s, empty_table(), centre);
  r.platform = empty_table();
  const render::ViewPlan placed = render::plan_view(g(), s, r);
  ASSERT_EQ(placed.marks.items.size(), 1u);
  const auto q = placed.camera.project(s.objects[cube].position);
  ASSERT_TRUE(q.has_value());
  const cv::Vec3b now = draw(s, placed).plain.at<cv::Vec3b>(cv::Point(static_cast<int>(q->x()), static_cast<int>(q->y())));
  EXPECT_GT(now[2], 2 * now[1]) << "the cube is drawn where it was placed";
}

TEST_F(RenderTest, BadRequestsGetOneLineErrorsAndTheRendererKeepsServing) {
  const episode::WorldState s = at(table());
  auto expect_error = [&](render::ImageRequest req, const std::string& what) {
    try {
      renderer_->render(req);
      ADD_FAILURE() << "no error for " << what;
    } catch (const Error& e) {
      EXPECT_THAT(e.what(), HasSubstr(what));
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  };
  expect_error(request(s, {{render::ViewKind::kPlatform, "no_such_platform", -1, "", render::MarkKind::kItems, 0, ""}}), "no platform 'no_such_platform'");
  auto zero = request(s, {platform_view(table(), render::MarkKind::kItems)});
  zero.height = 0;
  expect_error(zero, "image size 640x0");
  const graph::ObjectId ghost = object_of(g(), "toy_ghost");
  expect_error(request(s, {{render::ViewKind::kItem, "", -1, g().objects[ghost].name, render::MarkKind::kNone, 0, ""}}),
               "has no mesh to draw");
  auto state = request(s, {platform_view(table(), render::MarkKind::kItems)});
  state.state.held = "nobody";
  expect_error(state, "'held' names no object");
  auto encoding = request(s, {platform_view(table(), render::MarkKind::kItems)});
  encoding.encoding = "bmp";
  expect_error(encoding, "unknown encoding 'bmp'");
  // ... and the next good request is served as usual.
  const auto reply = renderer_->render(request(s, {platform_view(table(), render::MarkKind::kItems)}));
  ASSERT_EQ(reply.images.size(), 2u);
  EXPECT_EQ(decode(reply.images[0]).cols, 640);
  EXPECT_GT(reply.triangles, 0);
}

// The renderer draws every view, then encodes all the images at once on several threads: the
// reply must hold each view's images in order, with the bytes one thread would give.
TEST_F(RenderTest, AReplyHoldsEveryViewsImagesInOrderEncodedAsOneThreadWould) {
  const episode::WorldState s = at(table());
  const render::ViewSpec topdown{render::ViewKind::kTopdown, "", -1, "", render::MarkKind::kLabels, 0, ""};
  const std::vector<render::ViewSpec> views = {platform_view(table(), render::MarkKind::kItems),
                                               platform_view(empty_table(), render::MarkKind::kNone), topdown,
                                               platform_view(empty_table(), render::MarkKind::kTargets)};
  const render::ImageReply reply = renderer_->render(request(s, views));
  ASSERT_EQ(reply.images.size(), 7u);
  std::vector<std::vector<std::uint8_t>> expected;
  std::vector<std::string> roles;
  for (const render::ViewSpec& v : views) {
    render::ViewRequest r;
    r.view = v.view;
    if (v.view == render::ViewKind::kPlatform) r.platform = g().find_platform(v.platform);
    r.marks = v.marks;
    const render::ViewImages images = draw(s, render::plan_view(g(), s, r), v.marks != render::MarkKind::kNone);
    const std::string role = v.view == render::ViewKind::kTopdown ? "topdown" : "view";
    expected.push_back(render::encode_image(images.plain, "png"));
    roles.push_back(role);
    if (!images.marked.empty()) {
      expected.push_back(render::encode_image(images.marked, "png"));
      roles.push_back(role + "_marked");
    }
  }
  ASSERT_EQ(expected.size(), reply.images.size());
  for (std::size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(reply.images[k].role, roles[k]) << k;
    EXPECT_EQ(reply.images[k].bytes, expected[k]) << k;
  }
  // And on any number of threads.
  render::ViewRequest on_table;
  on_table.platform = table();
  const render::ViewImages images = draw(s, render::plan_view(g(), s, on_table), true);
  const std::vector<const cv::Mat*> both = {&images.plain, &images.marked};
  EXPECT_EQ(render::encode_images(both, "png", 1), render::encode_images(both, "png", 3));
  // An image that cannot be encoded fails the call with its own error, on any thread.
  const cv::Mat nothing;
  for (const int jobs : {1, 2}) {
    try {
      render::encode_images({&images.plain, &nothing, &images.marked}, "png", jobs);
      ADD_FAILURE() << "expected an error on " << jobs << " threads";
    } catch (const Error& e) {
      EXPECT_THAT(e.what(), HasSubstr("render: an empty image cannot be encoded as png"));
    }
  }
}

// Every object a placing option names carries a mark in the placing view (issue 53): an item its
// number, scenery (a TV box, a blanket) a letter of its own that the option quotes ("rear-right of
// the TV box marked A"), never "the TV box it is drawn next to" with nothing in the picture to
// find it by. Checked on every navigable platform of the shipped apartments, holding their
// smallest item.
TEST(ShippedRender, EveryObjectAPlacingOptionNamesCarriesAMark) {
  MTG_REQUIRE_SHIPPED_DATA();
  render::ImageRenderer renderer;
  const std::string data = testing::shipped_dataset()->root.string();
  int lettered_options = 0;
  for (const char* scene : {"apt_0", "apt_1", "apt_2"}) {
    const graph::SceneGraph& g = renderer.scenes().load(scene, data).graph;
    episode::WorldState start = episode::initial_state(g);
    const graph::ObjectId smallest = testing::smallest_item(g, start);
    ASSERT_TRUE(smallest.valid()) << scene;
    episode::pick(g, start, smallest);
    for (const graph::PlatformId p : g.navigable) {
      episode::WorldState s = start;
      s.at_platform = p;
      s.side = std::max(0, g.platforms[p].default_side);
      s.phase = episode::Phase::kPlacing;
      render::ViewRequest r;
      r.platform = p;
      r.marks = render::MarkKind::kTargets;
      const render::ViewPlan plan = render::plan_view(g, s, r);
      std::set<std::string> letters;
      for (const render::LabelMark& f : plan.marks.fixtures) letters.insert(f.text);
      EXPECT_EQ(letters.size(), plan.marks.fixtures.size()) << scene << " " << g.platforms[p].name;
      std::set<std::string> quoted;
      for (const episode::ActionOption& a : episode::action_space(g, s, episode::RuleOptions{})) {
        EXPECT_EQ(a.description.find("drawn next to"), std::string::npos) << a.description;
        const auto at = a.description.find(" marked ");
        if (at == std::string::npos) continue;
        const std::string letter = a.description.substr(at + 8);
        EXPECT_EQ(letters.count(letter), 1u) << scene << " " << g.platforms[p].name << ": " << a.description;
        quoted.insert(letter);
        ++lettered_options;
      }
      EXPECT_EQ(quoted, letters) << scene << " " << g.platforms[p].name << ": a letter no option quotes";
    }
  }
  std::printf("[ lettered ] %d placing options name scenery by its letter\n", lettered_options);
  EXPECT_GT(lettered_options, 0) << "no placing option of the shipped apartments names scenery";
}

TEST(ShippedRender, Apt0ShelfMatchesItsGoldenAndEveryPlatformViewHoldsItsItems) {
  MTG_REQUIRE_SHIPPED_DATA();
  render::ImageRenderer renderer;
  const std::string data = testing::shipped_dataset()->root.string();
  const graph::SceneGraph& g = renderer.scenes().load("apt_0", data).graph;
  const auto shelf = g.find_platform("wall_cabinet_02_30_platform_3");
  ASSERT_TRUE(shelf.valid());
  render::ImageRequest req;
  req.scene = "apt_0";
  req.data_dir = data;
  req.views = {{render::ViewKind::kPlatform, "wall_cabinet_02_30_platform_3", -1, "", render::MarkKind::kItems, 0, ""}};
  const auto reply = renderer.render(req);
  // The view, its marked copy, and a zoom of the small books (the shelf is seen from afar).
  ASSERT_EQ(reply.images.size(), 3u);
  EXPECT_EQ(reply.images[2].role, "view_zoom");
  EXPECT_EQ(testing::compare_golden_image("render/apt_0_wall_cabinet_shelf_marked.png", decode(reply.images[1])), "");
  EXPECT_EQ(testing::compare_golden_image("render/apt_0_wall_cabinet_shelf_zoom.png", decode(reply.images[2])), "");

  // Every navigable platform, from its default side: each numbered item that shows has a
  // readable mark in the view or a zoom of it, and no layout breaks a rule (mark_layout.h).
  const render::SceneGeometry& geometry = renderer.geometry(renderer.scenes().load("apt_0", data));
  const episode::WorldState s = episode::initial_state(g);
  int items = 0, shown = 0, placed = 0, zoomed_views = 0;
  for (const graph::PlatformId p : g.navigable) {
    render::ViewRequest r;
    r.platform = p;
    r.marks = render::MarkKind::kItems;
    const render::ViewPlan plan = render::plan_view(g, s, r);
    const render::ItemMarksPlan marks = render::plan_item_marks(g, geometry, s, plan.camera, plan.marks.items);
    EXPECT_EQ(marks.problems(), std::vector<std::string>{}) << g.platforms[p].name;
    zoomed_views += marks.zooms.empty() ? 0 : 1;
    for (const render::ItemMark& m : plan.marks.items) {
      ++items;
      const bool visible = std::any_of(marks.layout.placed.begin(), marks.layout.placed.end(),
                                       [&](const render::PlacedMark& pm) { return pm.number == m.number && pm.visible; }) ||
                           std::any_of(marks.layout.crowded.begin(), marks.layout.crowded.end(),
                                       [&](const render::ItemMark& c) { return c.number == m.number; });
      shown += visible ? 1 : 0;
      placed += visible && marks.placed(m.number) ? 1 : 0;
    }
  }
  std::printf("[ marks ] apt_0: %d items on %zu platforms, %d show, %d of them readably numbered; %d views zoomed\n",
              items, g.navigable.size(), shown, placed, zoomed_views);
  EXPECT_GT(items, 50);
  EXPECT_EQ(placed, shown);
}

// No free space or grid cell lies behind its platform's own furniture in the placing picture: on
// every navigable platform inside its furniture (a shelf, a TV stand's floor), of the shipped
// apartments and of held-out arrangements, holding the scene's smallest item at the arrival side,
// no target is more than half covered in the id pass by the owner, more than 3 cm in front of it
// (25 points over each target). A TV stand's floor ran on behind its closed doors and its cells
// were drawn on the doors (issue 53); such a platform is now the part reached through its opening
// (graph.md, "Reach"). What is still hidden is counted and may not grow.
TEST(ShippedRender, NoPlacingTargetIsBehindItsOwnFurniture) {
  MTG_REQUIRE_SHIPPED_DATA();
  int platforms = 0, targets = 0, hidden = 0;
  for (const char* name : {"apt_0", "apt_1", "apt_2"}) {
    for (const int remix : {-1, 3}) {
      const testing::ShippedScene shipped =
          remix < 0 ? testing::load_shipped_scene(name) : testing::load_remixed_scene(name, static_cast<std::uint64_t>(remix));
      const graph::SceneGraph& g = shipped.graph;
      const render::SceneGeometry geometry(shipped.scene, g);
      episode::WorldState holding = episode::initial_state(g);
      episode::pick(g, holding, testing::smallest_item(g, holding));
      for (const graph::PlatformId p : g.navigable) {
        if (!g.platforms[p].interior) continue;
        ++platforms;
        const int side = std::max(0, g.platforms[p].default_side);
        episode::WorldState s = holding;
        s.at_platform = p;
        s.side = side;
        s.phase = episode::Phase::kPlacing;
        const render::Camera camera = render::platform_pictures(g, s, p, side, 640, 480).front().camera;
        const render::IdView view = render::draw_id_view(g, geometry, s, camera);
        const auto owner = static_cast<std::int32_t>(g.platforms[p].owner.index());
        const Eigen::Isometry3d X_CW = camera.X_WC.inverse();
        // Whether the point (1 cm above the surface) is covered by the owner in the picture,
        // more than 3 cm nearer (the pixel's distance from its normalised depth, OpenGL's
        // projection); nullopt when it is outside the picture or shows something else.
        const auto behind_owner = [&](const Eigen::Vector3d& on_surface) -> std::optional<bool> {
          const Eigen::Vector3d point = on_surface + Eigen::Vector3d(0.0, 0.0, 0.01);
          const auto px = camera.project(point);
          if (!px || px->x() < 0.0 || px->y() < 0.0 || px->x() >= 640.0 || px->y() >= 480.0) return std::nullopt;
          const int u = static_cast<int>(px->x()), v = static_cast<int>(px->y());
          if (view.image.at(u, v) != owner) return false;
          const double z = view.image.depth[static_cast<std::size_t>(v) * 640 + static_cast<std::size_t>(u)];
          const double n = camera.near, f = camera.far;
          return 2.0 * f * n / ((f + n) - z * (f - n)) < -(X_CW * point).z() - 0.03;
        };
        for (const render::RegionMark& r : render::target_marks(g, s, p, static_cast<graph::Side>(side), 0.03)) {
          ++targets;
          // Points of the target all over it: a thin divider or a rail in front of one spot
          // hides that spot, a door or a panel most of the target.
          geom::Region region;
          for (const auto& ring : r.rings_W) {
            geom::Ring xy;
            for (const Eigen::Vector3d& q : ring) xy.emplace_back(q.x(), q.y());
            region.rings.push_back(std::move(xy));
          }
          const Eigen::AlignedBox2d box = geom::bounds(region);
          int looked = 0, covered = 0;
          for (int i = 0; i < 5; ++i) {
            for (int j = 0; j < 5; ++j) {
              const Eigen::Vector2d q = box.min() + Eigen::Vector2d((i + 0.5) / 5.0 * box.sizes().x(), (j + 0.5) / 5.0 * box.sizes().y());
              if (!geom::contains(region, q)) continue;
              const std::optional<bool> b = behind_owner(Eigen::Vector3d(q.x(), q.y(), r.label_W.z()));
              if (!b) continue;
              ++looked;
              covered += *b ? 1 : 0;
            }
          }
          if (looked > 0 && 2 * covered > looked) {
            ++hidden;
            std::printf("[ reach ] %s %s: target %d is %d/%d behind %s\n", shipped.scene.name.c_str(),
                        g.platforms[p].name.c_str(), r.number, covered, looked,
                        g.objects[g.platforms[p].owner].name.c_str());
          }
        }
      }
    }
  }
  std::printf("[ reach ] %d platforms inside their furniture, %d targets, %d behind the furniture\n", platforms,
              targets, hidden);
  EXPECT_GT(targets, 1000);
  // What is left is the picture, not the reach: the rear-centre cell of a fridge's top shelf
  // behind the bar standing in the middle of it (three apartments and a remix), and a low table
  // shelf seen between the table's legs (apt_1 and its remix). Before reach: 44, all six TV
  // stands' floors among them. No more may go.
  EXPECT_LE(hidden, 8);
}

// The picture of a whole platform holds what it frames (view.cc, plan_platform_pictures): the
// platform's outline and everything standing on it directly, bottom and top, inside the image, on
// every navigable platform of the shipped apartments and of held-out arrangements, from every
// side the robot can stand at. Before the lens held the box as it lay, an aim that had not settled
// cut off a TV stand's end (free spaces 1-113 px left of the picture) and a shelf's books.
TEST(ShippedRender, EveryPlatformPictureHoldsTheOutlineAndItemsItFrames) {
  MTG_REQUIRE_SHIPPED_DATA();
  int pictures = 0, points = 0;
  for (const char* name : {"apt_0", "apt_1", "apt_2"}) {
    for (const int remix : {-1, 3}) {
      const testing::ShippedScene shipped =
          remix < 0 ? testing::load_shipped_scene(name) : testing::load_remixed_scene(name, static_cast<std::uint64_t>(remix));
      const graph::SceneGraph& g = shipped.graph;
      const episode::WorldState s = episode::initial_state(g);
      for (const graph::PlatformId p : g.navigable) {
        const double h = episode::platform_height(g, s, p);
        std::vector<Eigen::Vector3d> keys;
        for (const geom::Ring& ring : g.platforms[p].polygon_W().rings) {
          for (const auto& q : ring) keys.emplace_back(q.x(), q.y(), h);
        }
        for (const graph::ObjectId o : episode::objects_on(s, p)) {
          for (const auto& q : s.objects[o].footprint) {
            keys.emplace_back(q.x(), q.y(), s.objects[o].bottom);
            keys.emplace_back(q.x(), q.y(), s.objects[o].top);
          }
        }
        for (int side = 0; side < 4; ++side) {
          if (g.platforms[p].sides[static_cast<std::size_t>(side)].standing_area <= 0.0) continue;
          const render::Camera camera = render::platform_pictures(g, s, p, side, 640, 480).front().camera;
          ++pictures;
          for (const Eigen::Vector3d& k : keys) {
            ++points;
            const auto px = camera.project(k);
            ASSERT_TRUE(px.has_value()) << shipped.scene.name << " " << g.platforms[p].name << " side " << side;
            EXPECT_TRUE(px->x() >= 0.0 && px->x() <= 640.0 && px->y() >= 0.0 && px->y() <= 480.0)
                << shipped.scene.name << " " << g.platforms[p].name << " side " << side << ": (" << k.transpose()
                << ") drawn at " << px->transpose();
          }
        }
      }
    }
  }
  std::printf("[ framing ] %d whole-platform pictures, %d key points\n", pictures, points);
  EXPECT_GT(pictures, 300);
}

// Free spaces follow the rules of item marks (target_layout.h): on every navigable platform of the
// shipped apartments, from the side the robot arrives at, every placement target is numbered in
// one of the view's pictures or a zoom of it, and no layout breaks a rule.
// Every placing view of the shipped apartments and of held-out arrangements (`mtg scene remix`,
// issue 53), holding the scene's smallest item (the most free spaces) at every navigable
// platform from the side the robot arrives at: every target offered has its number readably
// placed in one of the view's pictures or their zooms, and no layout breaks a rule (overlapping
// discs, a disc on another's label point, crossing leader lines). On the remixes 5 free spaces of
// 1,250 had their label point outside the picture until the camera's lens held what it frames
// (an aim that had not settled, docs/render.md, "Free spaces a person can read").
TEST(ShippedRender, EveryPlatformsFreeSpacesAreReadablyNumbered) {
  MTG_REQUIRE_SHIPPED_DATA();
  for (const char* name : {"apt_0", "apt_1", "apt_2"}) {
    for (const int remix : {-1, 3}) {
      const testing::ShippedScene shipped =
          remix < 0 ? testing::load_shipped_scene(name) : testing::load_remixed_scene(name, static_cast<std::uint64_t>(remix));
      const graph::SceneGraph& g = shipped.graph;
      const std::string& scene = shipped.scene.name;
      episode::WorldState holding = episode::initial_state(g);
      episode::pick(g, holding, testing::smallest_item(g, holding));
      int targets = 0, numbered = 0, zoomed = 0, broken = 0;
      for (const graph::PlatformId p : g.navigable) {
        const int side = std::max(0, g.platforms[p].default_side);
        episode::WorldState s = holding;
        s.at_platform = p;
        s.side = side;
        s.phase = episode::Phase::kPlacing;
        const auto regions = render::target_marks(g, s, p, static_cast<graph::Side>(side), 0.03);
        std::set<int> readable;
        for (const render::PlatformPicture& picture : render::platform_pictures(g, s, p, side, 640, 480)) {
          const auto plan = render::plan_target_marks(picture.camera, render::regions_in(g, s, p, side, picture, regions));
          EXPECT_EQ(plan.problems(), std::vector<std::string>{}) << scene << " " << g.platforms[p].name;
          broken += static_cast<int>(plan.problems().size());
          zoomed += plan.zooms.empty() ? 0 : 1;
          for (const render::RegionMark& r : regions) {
            if (plan.placed(r.number)) readable.insert(r.number);
          }
        }
        targets += static_cast<int>(regions.size());
        numbered += static_cast<int>(readable.size());
        for (const render::RegionMark& r : regions) {
          EXPECT_TRUE(readable.count(r.number)) << scene << " " << g.platforms[p].name << ": free space " << r.number;
        }
      }
      std::printf("[ targets ] %s: %d free spaces and cells on %zu platforms, %d readably numbered, %d rules broken; "
                  "%d pictures zoomed\n",
                  scene.c_str(), targets, g.navigable.size(), numbered, broken, zoomed);
    }
  }
}

TEST(ShippedRender, Apt0OverviewShowsEveryPlatformLabelWithoutOverlapAndFillsTheFrame) {
  MTG_REQUIRE_SHIPPED_DATA();
  render::ImageRenderer renderer;
  const graph::SceneGraph& g = renderer.scenes().load("apt_0", testing::shipped_dataset()->root.string()).graph;
  const episode::WorldState s = episode::initial_state(g);
  render::ViewRequest r;
  r.view = render::ViewKind::kTopdown;
  r.marks = render::MarkKind::kLabels;
  const render::ViewPlan plan = render::plan_view(g, s, r);
  const auto placed = render::place_labels(plan.camera, plan.marks.labels);
  // Every navigable platform has its label, in the image, covering no other label.
  ASSERT_EQ(placed.size(), g.navigable.size());
  const cv::Rect frame(0, 0, 640, 480);
  for (std::size_t i = 0; i < placed.size(); ++i) {
    EXPECT_EQ(placed[i].box & frame, placed[i].box) << placed[i].text;
    for (std::size_t j = i + 1; j < placed.size(); ++j) {
      EXPECT_EQ((placed[i].box & placed[j].box).area(), 0) << placed[i].text << " covers " << placed[j].text;
    }
  }
  // The platforms' anchors span most of the image's long side (the map is turned to fit).
  int lo = 640, hi = 0;
  for (const auto& p : placed) {
    lo = std::min(lo, p.anchor.x);
    hi = std::max(hi, p.anchor.x);
  }
  EXPECT_GT(hi - lo, 0.75 * 640) << "platforms span x " << lo << ".." << hi;
}

}  // namespace
}  // namespace mtg
