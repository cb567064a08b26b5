#include "core/graph/free_space.h"

#include <algorithm>
#include <limits>
#include <string>

#include "core/util/error.h"

namespace mtg::graph {
namespace {

constexpr double kEps = 1e-9;

Eigen::AlignedBox2d box(double x0, double y0, double x1, double y1) {
  return Eigen::AlignedBox2d(Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y1));
}

bool open_overlap(double a0, double a1, double b0, double b1) { return a0 < b1 - kEps && b0 < a1 - kEps; }

// Side region of `a` towards `dir` (0 rear, 2 left, 4 front, 6 right), cut at the first obstacle.
Eigen::AlignedBox2d side_rect(const Eigen::AlignedBox2d& a, int dir, const Eigen::AlignedBox2d& limit,
                              const std::vector<Obstacle>& obstacles, ObjectId self) {
  const double ax0 = a.min().x(), ax1 = a.max().x(), ay0 = a.min().y(), ay1 = a.max().y();
  switch (dir) {
    case 0: {  // rear: y below the object
      double far = limit.min().y();
      for (const auto& o : obstacles) {
        if (o.object == self || !open_overlap(ax0, ax1, o.box_P.min().x(), o.box_P.max().x())) continue;
        if (o.box_P.min().y() >= ay0 - kEps) continue;  // entirely in front of the edge
        far = std::max(far, std::min(o.box_P.max().y(), ay0));
      }
      return box(ax0, far, ax1, ay0);
    }
    case 4: {  // front
      double far = limit.max().y();
      for (const auto& o : obstacles) {
        if (o.object == self || !open_overlap(ax0, ax1, o.box_P.min().x(), o.box_P.max().x())) continue;
        if (o.box_P.max().y() <= ay1 + kEps) continue;
        far = std::min(far, std::max(o.box_P.min().y(), ay1));
      }
      return box(ax0, ay1, ax1, far);
    }
    case 2: {  // left: x below
      double far = limit.min().x();
      for (const auto& o : obstacles) {
        if (o.object == self || !open_overlap(ay0, ay1, o.box_P.min().y(), o.box_P.max().y())) continue;
        if (o.box_P.min().x() >= ax0 - kEps) continue;
        far = std::max(far, std::min(o.box_P.max().x(), ax0));
      }
      return box(far, ay0, ax0, ay1);
    }
    default: {  // 6 right
      double far = limit.max().x();
      for (const auto& o : obstacles) {
        if (o.object == self || !open_overlap(ay0, ay1, o.box_P.min().y(), o.box_P.max().y())) continue;
        if (o.box_P.max().x() <= ax1 + kEps) continue;
        far = std::min(far, std::max(o.box_P.min().x(), ax1));
      }
      return box(ax1, ay0, far, ay1);
    }
  }
}

// Corner region: the largest rectangle anchored at the object's corner (sx, sy say which way
// it grows: -1 towards smaller coordinates) holding no obstacle.
Eigen::AlignedBox2d corner_rect(const Eigen::AlignedBox2d& a, int sx, int sy,
                                const Eigen::AlignedBox2d& limit,
                                const std::vector<Obstacle>& obstacles, ObjectId self) {
  const double cx = sx < 0 ? a.min().x() : a.max().x();
  const double cy = sy < 0 ? a.min().y() : a.max().y();
  const double u_max = std::max(0.0, sx < 0 ? cx - limit.min().x() : limit.max().x() - cx);
  const double v_max = std::max(0.0, sy < 0 ? cy - limit.min().y() : limit.max().y() - cy);
  // Obstacles in quadrant coordinates (u, v >= 0 away from the corner).
  struct Quad { double u0, v0; };
  std::vector<Quad> quads;
  for (const auto& o : obstacles) {
    if (o.object == self) continue;
    const double u0 = sx < 0 ? cx - o.box_P.max().x() : o.box_P.min().x() - cx;
    const double u1 = sx < 0 ? cx - o.box_P.min().x() : o.box_P.max().x() - cx;
    const double v0 = sy < 0 ? cy - o.box_P.max().y() : o.box_P.min().y() - cy;
    const double v1 = sy < 0 ? cy - o.box_P.min().y() : o.box_P.max().y() - cy;
    if (u1 <= kEps || v1 <= kEps || u0 >= u_max || v0 >= v_max) continue;  // not in the quadrant
    quads.push_back({std::max(0.0, u0), std::max(0.0, v0)});
  }
  std::vector<double> widths = {u_max};
  for (const auto& q : quads) widths.push_back(q.u0);
  std::sort(widths.begin(), widths.end());
  // A rectangle u wide may reach up to the nearest obstacle that starts before u. Widths grow, so
  // those obstacles only ever join: with them by their start, the bound is a running minimum
  // (the same minimum, over the same obstacles, as asking each of them at every width).
  std::sort(quads.begin(), quads.end(), [](const Quad& p, const Quad& q) { return p.u0 < q.u0; });
  double best_u = 0.0, best_v = 0.0, best_area = -1.0;
  double v = v_max;
  std::size_t started = 0;
  for (const double u : widths) {
    for (; started < quads.size() && quads[started].u0 < u - kEps; ++started) v = std::min(v, quads[started].v0);
    if (u <= kEps) continue;
    if (u * v > best_area + 1e-12) {
      best_area = u * v;
      best_u = u;
      best_v = v;
    }
  }
  const double x0 = sx < 0 ? cx - best_u : cx, x1 = sx < 0 ? cx : cx + best_u;
  const double y0 = sy < 0 ? cy - best_v : cy, y1 = sy < 0 ? cy : cy + best_v;
  return box(x0, y0, x1, y1);
}

}  // namespace

const char* direction_name(int dir) {
  static constexpr const char* kNames[9] = {"rear",  "rear-left",   "left",  "front-left", "front",
                                            "front-right", "right", "rear-right", "center"};
  return dir >= 0 && dir <= 8 ? kNames[dir] : "?";
}

int platform_direction(int relative, Side side) {
  if (relative == kCentre) return kCentre;
  return (relative + 2 * static_cast<int>(side)) % kNumDirections;
}

Eigen::Vector2i direction_step(int dir) {
  static const Eigen::Vector2i kStep[9] = {{0, -1}, {-1, -1}, {-1, 0}, {-1, 1}, {0, 1},
                                           {1, 1},  {1, 0},   {1, -1}, {0, 0}};
  MTG_DEMAND(dir >= 0 && dir <= kCentre, "direction " + std::to_string(dir) + " out of range");
  return kStep[dir];
}

int relative_direction(int platform_dir, Side side) {
  if (platform_dir == kCentre) return kCentre;
  return (platform_dir - 2 * static_cast<int>(side) + 2 * kNumDirections) % kNumDirections;
}

std::vector<Obstacle> make_obstacles(const Platform& platform, const std::vector<ObjectId>& objects,
                                     const std::vector<geom::Ring>& footprints_W) {
  std::vector<Obstacle> out;
  const Eigen::Isometry2d X_PW = platform.X_WP.inverse();
  for (std::size_t k = 0; k < objects.size(); ++k) {
    Obstacle o;
    o.object = objects[k];
    o.hull_P = geom::transform(footprints_W.at(k), X_PW);
    o.box_P = geom::bounds(o.hull_P);
    out.push_back(std::move(o));
  }
  return out;
}

namespace {

// A platform that fills its bounding box clips nothing: regions inside the box stay rectangles.
bool fills_its_box(const Platform& platform) {
  return geom::area(platform.polygon_P) >= platform.box_P.volume() * (1.0 - 1e-9);
}

geom::Region clip_to_platform(const Platform& platform, bool rectangular, const Eigen::AlignedBox2d& rect,
                              const RectClip& clip = {}) {
  if (rectangular) return geom::rectangle(rect.min(), rect.max());
  return clip ? clip(rect) : clip_to_polygon(platform, rect);
}

}  // namespace

geom::Region clip_to_polygon(const Platform& platform, const Eigen::AlignedBox2d& rect) {
  return geom::intersect(platform.polygon_P, geom::rectangle(rect.min(), rect.max()));
}

std::vector<FreeRegion> object_regions(const Platform& platform, const std::vector<Obstacle>& obstacles,
                                       double min_size, const RectClip& clip) {
  std::vector<FreeRegion> out;
  const Eigen::AlignedBox2d limit = platform.box_P;
  const bool rectangular = fills_its_box(platform);
  for (const Obstacle& a : obstacles) {
    for (int dir = 0; dir < kNumDirections; ++dir) {
      FreeRegion r;
      r.object = a.object;
      r.dir = dir;
      r.rect_P = dir % 2 == 0 ? side_rect(a.box_P, dir, limit, obstacles, a.object)
                              : corner_rect(a.box_P, direction_step(dir).x(), direction_step(dir).y(), limit,
                                            obstacles, a.object);
      const Eigen::Vector2d size = r.rect_P.sizes();
      if (size.x() > kEps && size.y() > kEps) r.region_P = clip_to_platform(platform, rectangular, r.rect_P, clip);
      const Eigen::AlignedBox2d clipped = geom::bounds(r.region_P);
      r.numbered = !r.region_P.empty() && clipped.sizes().x() >= min_size &&
                   clipped.sizes().y() >= min_size;
      out.push_back(std::move(r));
    }
  }
  return out;
}

Eigen::AlignedBox2d grid_cell_rect(const Platform& platform, int dir) {
  // Column along x (0 left .. 2 right) and row along y (0 rear .. 2 front) of the direction.
  const Eigen::Vector2i cell = direction_step(dir) + Eigen::Vector2i(1, 1);
  const Eigen::Vector2d step = platform.box_P.sizes() / 3.0;
  const Eigen::Vector2d a = platform.box_P.min() + Eigen::Vector2d(cell.x() * step.x(), cell.y() * step.y());
  return Eigen::AlignedBox2d(a, a + step);
}

std::array<FreeRegion, 9> grid_cells(const Platform& platform) {
  std::array<FreeRegion, 9> out;
  const bool rectangular = fills_its_box(platform);
  for (int dir = 0; dir <= kCentre; ++dir) {
    FreeRegion& r = out[static_cast<std::size_t>(dir)];
    r.dir = dir;
    r.rect_P = grid_cell_rect(platform, dir);
    r.region_P = clip_to_platform(platform, rectangular, r.rect_P);
    r.numbered = !r.region_P.empty();
  }
  return out;
}

geom::Ring minkowski_convex(const geom::Ring& a, const geom::Ring& b) { return geom::convex_hull_of_sums(a, b); }

geom::Region placeable_interior(const Platform& platform, const geom::Ring& item_hull) {
  return geom::erode(platform.polygon_P, item_hull);
}

geom::Region clear_of(const geom::Region& inside, const std::vector<Obstacle>& obstacles, const geom::Ring& item_hull) {
  if (inside.empty() || obstacles.empty()) return inside;
  const geom::Ring minus_item = geom::mirrored(item_hull);
  std::vector<geom::Ring> blocked;
  for (const Obstacle& o : obstacles) blocked.push_back(minkowski_convex(o.hull_P, minus_item));
  return geom::subtract(inside, geom::unite_rings(blocked));
}

geom::Region feasible_positions(const Platform& platform, const std::vector<Obstacle>& obstacles,
                                const geom::Ring& item_hull) {
  return clear_of(placeable_interior(platform, item_hull), obstacles, item_hull);
}

}  // namespace mtg::graph
