#include "core/geom/polygon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace mtg::geom {
namespace {

Ring square(double cx, double cy, double half) {
  return {{cx - half, cy - half}, {cx + half, cy - half}, {cx + half, cy + half}, {cx - half, cy + half}};
}

// offset() returns ClipperOffset's rings as they come (no union after it): outer rings must still
// be counter-clockwise and holes clockwise, growing and shrinking, with and without holes, and
// a region that shrinks away or splits in two.
TEST(Polygon, OffsetRingsAreOrientedLikeEveryOtherResult) {
  const Region frame = subtract(rectangle({0, 0}, {3, 3}), rectangle({1, 1}, {2, 2}));  // one hole
  const Region dumbbell = unite(unite(rectangle({0, 0}, {1, 1}), rectangle({2, 0}, {3, 1})), rectangle({1, 0.45}, {2, 0.55}));
  for (const Region& r : {frame, dumbbell, rectangle({0, 0}, {1, 0.5})}) {
    for (const double d : {0.2, 0.01, -0.01, -0.1, -0.3}) {
      const Region o = offset(r, d);
      double outer = 0.0, holes = 0.0;
      for (const Ring& ring : o.rings) (signed_area(ring) > 0 ? outer : holes) += signed_area(ring);
      EXPECT_NEAR(area(o), area(unite(o, o)), 1e-9) << d;  // the same set a union gives
      if (!o.empty()) {
        EXPECT_GT(outer, 0.0) << d;
      }
      EXPECT_NEAR(outer + holes, area(o), 1e-12) << d;
    }
  }
  // The frame's hole grows as the frame shrinks: 0.1 on every side of the 1 x 1 hole.
  const Region shrunk = offset(frame, -0.1);
  EXPECT_NEAR(area(shrunk), 2.8 * 2.8 - 1.2 * 1.2, 1e-6);
  ASSERT_EQ(shrunk.rings.size(), 2u);
  EXPECT_EQ((signed_area(shrunk.rings[0]) > 0) + (signed_area(shrunk.rings[1]) > 0), 1);
  // The dumbbell's bar (0.1 wide) vanishes at -0.1: two parts, both counter-clockwise.
  const Region split = offset(dumbbell, -0.1);
  ASSERT_EQ(split.rings.size(), 2u);
  for (const Ring& ring : split.rings) EXPECT_GT(signed_area(ring), 0.0);
  EXPECT_TRUE(offset(rectangle({0, 0}, {1, 0.5}), -0.3).empty());
}

// Clipper works on a 1 µm integer grid; the conversion rounds as std::llround does (halves away
// from zero), to the bit, also at halves and their neighbours, negative or not.
TEST(Polygon, CoordinatesRoundToTheMicrometreAsLlroundDoes) {
  std::vector<double> xs = {0.0, -0.0, 0.5e-6, -0.5e-6, 2.5e-6, -2.5e-6, 1.0000005, -3.0000015, 123.4567895};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int k = 0; k < 200; ++k) {
    const double half = (std::floor(u(rng) * 1e6) + 0.5) / 1e6;
    xs.insert(xs.end(), {half, std::nextafter(half, 1e9), std::nextafter(half, -1e9), u(rng)});
  }
  for (const double x : xs) {
    const Region r = from_ring({{x, 0.0}, {x + 1.0, 0.0}, {x + 1.0, 1.0}, {x, 1.0}});
    ASSERT_EQ(r.rings.size(), 1u) << x;
    const double expected = static_cast<double>(std::llround(x * 1e6)) / 1e6;
    const auto leftmost = std::min_element(r.rings[0].begin(), r.rings[0].end(),
                                           [](const Point2& a, const Point2& b) { return a.x() < b.x(); });
    EXPECT_EQ(leftmost->x(), expected) << std::hexfloat << x;
  }
}

TEST(Polygon, AreaUnionIntersectionDifference) {
  const Region a = rectangle({0, 0}, {2, 1});
  const Region b = rectangle({1, 0}, {3, 1});
  EXPECT_NEAR(area(a), 2.0, 1e-9);
  EXPECT_NEAR(area(unite(a, b)), 3.0, 1e-9);
  EXPECT_NEAR(area(intersect(a, b)), 1.0, 1e-9);
  EXPECT_NEAR(area(subtract(a, b)), 1.0, 1e-9);
  EXPECT_TRUE(intersect(a, rectangle({5, 5}, {6, 6})).empty());
}

TEST(Polygon, HoleIsSubtractedAndPointsClassified) {
  const Region ring_shape = subtract(rectangle({0, 0}, {3, 3}), rectangle({1, 1}, {2, 2}));
  EXPECT_NEAR(area(ring_shape), 8.0, 1e-9);
  EXPECT_TRUE(contains(ring_shape, {0.5, 0.5}));
  EXPECT_FALSE(contains(ring_shape, {1.5, 1.5}));
  EXPECT_EQ(components(ring_shape).size(), 1u);
  EXPECT_EQ(components(unite(rectangle({0, 0}, {1, 1}), rectangle({2, 0}, {3, 1}))).size(), 2u);
}

// intersect() leaves out the rings outside the other operand's box (a free space with a hole per
// object, against one small target): the point set must be what the rings give together.
TEST(Polygon, IntersectingAFreeSpaceWithManyHolesKeepsEveryHoleThatMatters) {
  Region free = rectangle({0, 0}, {2, 1});
  std::vector<Ring> holes;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 4; ++j) holes.push_back(square(0.1 + 0.22 * i, 0.12 + 0.25 * j, 0.05));
  }
  free = subtract(free, unite_rings(holes));
  ASSERT_EQ(free.rings.size(), 37u);
  for (const auto& [min, max] : {std::pair<Point2, Point2>{{0.3, 0.3}, {0.5, 0.45}}, {{0.0, 0.0}, {0.12, 0.2}},
                                 {{1.1, 0.05}, {1.9, 0.95}}, {{-1.0, -1.0}, {3.0, 2.0}}}) {
    const Region target = rectangle(min, max);
    const double expected = area(target) - area(subtract(target, free));  // not through intersect()
    EXPECT_NEAR(area(intersect(free, target)), expected, 1e-9);
    EXPECT_NEAR(area(intersect(target, free)), expected, 1e-9);
  }
  EXPECT_TRUE(intersect(free, rectangle({2.5, 0}, {3, 1})).empty()) << "disjoint boxes";
}

TEST(Polygon, ErodeByASquareShrinksEachSide) {
  // Positions of a 0.2 m square's centre inside a 1 x 0.6 rectangle: 0.8 x 0.4.
  const Region e = erode(rectangle({0, 0}, {1, 0.6}), square(0, 0, 0.1));
  EXPECT_NEAR(area(e), 0.8 * 0.4, 1e-9);
  const auto b = bounds(e);
  EXPECT_NEAR(b.min().x(), 0.1, 1e-6);
  EXPECT_NEAR(b.max().y(), 0.5, 1e-6);
  // An L-shaped region: a 0.4 square fits only in the wide leg.
  const Region l = unite(rectangle({0, 0}, {1, 0.5}), rectangle({0, 0}, {0.3, 2}));
  EXPECT_NEAR(area(erode(l, square(0, 0, 0.2))), 0.6 * 0.1, 1e-9);
}

TEST(Polygon, DilateConvexAddsThePattern) {
  const Region d = dilate(rectangle({0, 0}, {1, 1}), square(0, 0, 0.5));
  EXPECT_NEAR(area(d), 4.0, 1e-9);
}

TEST(Polygon, ConvexHullIsCounterClockwiseAndCanonical) {
  const Ring hull = convex_hull({{1, 1}, {0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 0.5}});
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_GT(signed_area(hull), 0.0);
  EXPECT_EQ(hull.front(), Point2(0, 0));
}

// The Minkowski sums of placement (an obstacle's footprint and an item's, both convex) must be
// convex_hull's to the bit, or task placements would move: rotated and axis-aligned boxes (whose
// sums tie in x), random hulls at metre-scale coordinates, repeated points, and tiny rings.
TEST(Polygon, TheHullOfSumsIsTheHullOfEverySumToTheBit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto box = [&](double cx, double cy, double hx, double hy, double yaw) {
    Ring r;
    for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
      const double x = sx * hx, y = sy * hy;
      r.push_back({cx + std::cos(yaw) * x - std::sin(yaw) * y, cy + std::sin(yaw) * x + std::cos(yaw) * y});
    }
    return r;
  };
  const auto random_hull = [&](int n, double scale, double cx, double cy) {
    std::vector<Point2> pts;
    for (int i = 0; i < n; ++i) pts.push_back({cx + scale * u(rng), cy + scale * u(rng)});
    return convex_hull(pts);
  };
  const auto same_bits = [](const Ring& a, const Ring& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Point2)) == 0;
  };
  std::vector<std::pair<Ring, Ring>> cases = {
      {box(1.25, -3.5, 0.2, 0.1, 0.0), box(0.0, 0.0, 0.05, 0.05, 0.0)},
      {box(1.25, -3.5, 0.2, 0.1, 0.0), box(0.0, 0.0, 0.1, 0.2, 0.0)},
      {square(0.3, 0.3, 0.1), square(-0.3, -0.3, 0.1)},
      {{{0.5, 0.5}}, square(0, 0, 0.1)},
      {{{0.5, 0.5}, {0.5, 0.5}, {0.7, 0.5}}, {{0.1, 0.1}, {0.2, 0.2}}},
      // x one ulp apart in b, equal once 3 is added: the run's y order is put right (this path of
      // the code runs; no case found shows a hull that depends on it).
      {{{3.0, 0.0}, {3.5, 0.0}, {3.5, 1.0}},
       {{0.1, 0.5}, {std::nextafter(0.1, 1.0), 0.2}, {0.3, 0.1}, {0.3, 0.9}}},
  };
  for (int k = 0; k < 300; ++k) {
    const double yaw = k % 3 == 0 ? 0.0 : u(rng) * M_PI;
    cases.push_back({box(3 * u(rng), 3 * u(rng), 0.3 * std::abs(u(rng)) + 0.01, 0.3 * std::abs(u(rng)) + 0.01, yaw),
                     mirrored(box(0, 0, 0.1, 0.05, k % 2 == 0 ? 0.0 : yaw))});
    cases.push_back({random_hull(20 + k % 30, 0.4, 3 * u(rng), 3 * u(rng)), mirrored(random_hull(12, 0.1, 0, 0))});
  }
  // The sum is walked edge by edge where both rings are convex and go round once: rings turned
  // into a platform's frame (turns that round to a hair to the right), many-sided rings with
  // nearly parallel edges, exactly parallel edges at any angle, and rings the walk must leave to
  // the sort (clockwise, a pentagram, repeated points).
  const auto turned = [](Ring r, double yaw, double cx, double cy) {
    for (Point2& q : r) q = Point2(cx + std::cos(yaw) * q.x() - std::sin(yaw) * q.y(), cy + std::sin(yaw) * q.x() + std::cos(yaw) * q.y());
    return r;
  };
  const auto circle = [](int n, double radius, double phase) {
    Ring r;
    for (int i = 0; i < n; ++i) r.push_back({radius * std::cos(phase + 2 * M_PI * i / n), radius * std::sin(phase + 2 * M_PI * i / n)});
    return r;
  };
  for (int k = 0; k < 400; ++k) {
    const double yaw = u(rng) * M_PI;
    cases.push_back({turned(random_hull(8 + k % 40, 0.5, 0, 0), yaw, 3 * u(rng), 3 * u(rng)),
                     mirrored(turned(random_hull(4 + k % 12, 0.15, 0, 0), u(rng) * M_PI, 0, 0))});
    cases.push_back({turned(circle(16 + k % 50, 0.4, u(rng)), yaw, u(rng), u(rng)), mirrored(circle(8 + k % 20, 0.1, u(rng)))});
    cases.push_back({box(3 * u(rng), 3 * u(rng), 0.25, 0.1, yaw), mirrored(box(0, 0, 0.05, 0.08, yaw + (k % 4) * M_PI / 2))});
    cases.push_back({turned(circle(8, 0.3, 0), yaw, u(rng), u(rng)), turned(circle(4, 0.1, M_PI / 4), yaw, 0, 0)});
  }
  Ring clockwise = square(0.2, 0.1, 0.3);
  std::reverse(clockwise.begin(), clockwise.end());
  Ring pentagram;
  for (int i = 0; i < 5; ++i) pentagram.push_back({std::cos(4 * M_PI * i / 5), std::sin(4 * M_PI * i / 5)});
  cases.push_back({clockwise, square(0, 0, 0.1)});
  cases.push_back({pentagram, square(0, 0, 0.1)});
  cases.push_back({square(0, 0, 0.1), pentagram});
  cases.push_back({{{0, 0}, {1, 0}, {1, 0}, {1, 1}}, circle(7, 0.2, 0.1)});
  // A spike out and back along a vertical edge: no turn to the right, x changes sign twice.
  const Ring spike = {{0, 0}, {2, 0}, {2, 3}, {2, 1}, {2, 2}, {0, 2}};
  const Ring diamond = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  cases.push_back({spike, diamond});
  cases.push_back({diamond, spike});
  cases.push_back({turned(spike, 0.3, 1, 1), diamond});
  for (const auto& [a, b] : cases) {
    std::vector<Point2> sums;
    for (const Point2& p : a) {
      for (const Point2& q : b) sums.push_back(p + q);
    }
    EXPECT_TRUE(same_bits(convex_hull_of_sums(a, b), convex_hull(sums))) << a.size() << " x " << b.size();
  }
  EXPECT_TRUE(convex_hull_of_sums({}, square(0, 0, 1)).empty());
}

TEST(Polygon, MinAreaRectPicksTheAxisNearestThePreferredYaw) {
  // A 2 x 1 rectangle rotated by 30 deg.
  const Eigen::Rotation2Dd R(M_PI / 6);
  Ring r;
  for (const auto& p : square(0, 0, 1)) r.push_back(R * Point2(p.x(), 0.5 * p.y()));
  const OrientedBox near0 = min_area_rect(convex_hull(r), 0.0);
  EXPECT_NEAR(near0.yaw, M_PI / 6, 1e-9);
  EXPECT_NEAR(near0.half.x(), 1.0, 1e-9);
  EXPECT_NEAR(near0.half.y(), 0.5, 1e-9);
  const OrientedBox near90 = min_area_rect(convex_hull(r), M_PI / 2);
  EXPECT_NEAR(near90.yaw, M_PI / 6 + M_PI / 2, 1e-9);
  EXPECT_NEAR(near90.half.x(), 0.5, 1e-9);  // axes swap with the quarter turn
}

TEST(Polygon, ClosestPointOfARegion) {
  const Region r = rectangle({0, 0}, {1, 1});
  EXPECT_TRUE(closest_point(r, {0.5, 0.5}).isApprox(Point2(0.5, 0.5)));
  EXPECT_TRUE(closest_point(r, {2.0, 0.5}).isApprox(Point2(1.0, 0.5), 1e-6));
}

}  // namespace
}  // namespace mtg::geom
