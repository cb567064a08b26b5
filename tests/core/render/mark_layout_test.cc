// Marks a person can read (mark_layout.h): on id images made here, every placed mark keeps the
// rules (check_layout finds nothing), a big object gets its disc on itself, a crowd of small ones
// leaves some to a zoomed view aimed at them, and an object that shows nowhere gets a grey mark
// at its projected place.

#include <gtest/gtest.h>

#include "core/render/mark_layout.h"
#include "core/render/target_layout.h"

namespace mtg::render {
namespace {

// Fills a rectangle of the pass with object `id`.
void fill(IdImage& img, int u0, int v0, int w, int h, std::int32_t id) {
  for (int v = v0; v < v0 + h; ++v) {
    for (int u = u0; u < u0 + w; ++u) img.ids[static_cast<std::size_t>(v) * img.width + u] = id;
  }
}

Camera camera() {
  Camera c;
  c.width = 640;
  c.height = 480;
  c.fovy = 1.0;
  c.X_WC = look_at({0, -3, 2}, {0, 0, 0.8});
  return c;
}

ItemMark mark(int number, int object) { return {number, graph::ObjectId::of_index(object), Eigen::Vector3d(0, 0, 0.8)}; }

TEST(MarkLayout, ABigObjectCarriesItsNumberAndSmallNeighboursGetLinesThatKeepTheRules) {
  IdImage ids(320, 240);
  fill(ids, 40, 60, 120, 90, 0);   // a big board
  fill(ids, 200, 100, 8, 8, 1);    // three small jars in a row
  fill(ids, 210, 100, 8, 8, 2);
  fill(ids, 220, 100, 8, 8, 3);
  const std::vector<ItemMark> items = {mark(1, 0), mark(2, 1), mark(3, 2), mark(4, 3)};
  const MarkLayout layout = layout_item_marks(ids, 2, camera(), items);
  EXPECT_EQ(check_layout(layout, ids, 2, 640, 480), std::vector<std::string>{});
  ASSERT_EQ(layout.placed.size() + layout.crowded.size(), 4u);
  const auto big = std::find_if(layout.placed.begin(), layout.placed.end(), [](const PlacedMark& m) { return m.number == 1; });
  ASSERT_NE(big, layout.placed.end());
  EXPECT_TRUE(big->on_object()) << "the board holds its own disc";
  for (const PlacedMark& m : layout.placed) {
    EXPECT_TRUE(m.visible);
    // The dot is on the object's pixels.
    EXPECT_EQ(ids.at(static_cast<int>(m.anchor.x() / 2), static_cast<int>(m.anchor.y() / 2)),
              static_cast<std::int32_t>(m.object.index()));
  }
  EXPECT_FALSE(layout.small.empty()) << "8 x 8 pass pixels are 256 image pixels: shown larger in a zoom";
  const auto zooms = zoom_views(camera(), layout, items, true);
  ASSERT_EQ(zooms.size(), 1u);
  EXPECT_LT(zooms[0].camera.fovy, camera().fovy / 2.0 + 1e-9) << "at least twice as big";
  EXPECT_TRUE(zooms[0].region.contains(Eigen::Vector2d(428, 208))) << "aimed at the jars";
}

TEST(MarkLayout, ACrowdThatCannotBeNumberedReadablyIsLeftToAZoom) {
  IdImage ids(320, 240);
  std::vector<ItemMark> items;
  int object = 0;
  for (int row = 0; row < 4; ++row) {
    for (int col = 0; col < 8; ++col) {
      fill(ids, 140 + 5 * col, 110 + 5 * row, 4, 4, object);
      items.push_back(mark(object + 1, object));
      ++object;
    }
  }
  const MarkLayout layout = layout_item_marks(ids, 2, camera(), items);
  EXPECT_EQ(check_layout(layout, ids, 2, 640, 480), std::vector<std::string>{});
  EXPECT_FALSE(layout.crowded.empty()) << "32 objects in 40 x 20 pass pixels cannot all be numbered there";
  const auto zooms = zoom_views(camera(), layout, items, false);
  ASSERT_FALSE(zooms.empty());
  std::size_t covered = 0;
  for (const ZoomView& z : zooms) covered += z.items.size();
  EXPECT_GE(covered, layout.crowded.size()) << "every crowded mark is in some zoom";
}

TEST(MarkLayout, AnObjectThatShowsNowhereGetsAGreyMarkAtItsPlace) {
  IdImage ids(320, 240);
  fill(ids, 100, 100, 30, 30, 0);
  const std::vector<ItemMark> items = {mark(1, 0), mark(2, 5)};
  const MarkLayout layout = layout_item_marks(ids, 2, camera(), items);
  ASSERT_EQ(layout.placed.size(), 2u);
  EXPECT_FALSE(layout.placed[1].visible);
  const auto at = camera().project(items[1].anchor_W);
  ASSERT_TRUE(at.has_value());
  EXPECT_NEAR((layout.placed[1].anchor - *at).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace mtg::render

namespace mtg::render {
namespace {

// A region mark whose label point is `at` on the floor plane z = 0.8 (a square around it).
RegionMark target(int number, const Eigen::Vector3d& at) {
  RegionMark r;
  r.number = number;
  r.label_W = at;
  r.rings_W = {{at + Eigen::Vector3d(-0.01, -0.01, 0), at + Eigen::Vector3d(0.01, -0.01, 0),
                at + Eigen::Vector3d(0.01, 0.01, 0), at + Eigen::Vector3d(-0.01, 0.01, 0)}};
  return r;
}

// Free spaces follow the item marks' rules (target_layout.h): forty label points packed along a
// counter leave some numbers to zoomed views; every one ends up numbered, and no layout breaks a
// rule; two free spaces over one spot (the gap between two objects) are both numbered.
TEST(TargetLayout, CrowdedFreeSpacesGoToZoomsAndEveryNumberIsPlacedByTheRules) {
  std::vector<RegionMark> regions;
  for (int k = 0; k < 40; ++k) regions.push_back(target(k + 1, Eigen::Vector3d(-0.6 + 0.03 * k, (k % 2) * 0.03, 0.8)));
  regions.push_back(target(41, regions[10].label_W));  // the same spot as number 11
  const TargetMarksPlan plan = plan_target_marks(camera(), regions);
  EXPECT_FALSE(plan.layout.crowded.empty()) << "forty numbers 3 cm apart cannot all sit in the picture";
  EXPECT_FALSE(plan.zooms.empty());
  EXPECT_EQ(plan.frames.size() + [&] {
    std::size_t inner = 0;
    for (const TargetZoom& z : plan.zooms) inner += z.frames.size();
    return inner;
  }(), plan.zooms.size());
  EXPECT_EQ(plan.problems(), std::vector<std::string>{});
  for (const RegionMark& r : regions) EXPECT_TRUE(plan.placed(r.number)) << "free space " << r.number;
  // A label point outside the picture is neither placed nor crowded.
  const TargetLayout off = layout_target_marks(camera(), {target(1, Eigen::Vector3d(40, 0, 0.8))});
  EXPECT_TRUE(off.placed.empty());
  EXPECT_TRUE(off.crowded.empty());
}

}  // namespace
}  // namespace mtg::render
