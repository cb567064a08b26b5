#include "core/graph/standing.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/util/error.h"

namespace mtg::graph {

FloorRaster::FloorRaster(const std::vector<const geom::TriangleSoup*>& obstacles, const std::vector<bool>& steppable,
                         const GraphOptions& options)
    : resolution_(options.raster_resolution) {
  MTG_DEMAND(steppable.size() == obstacles.size(), "floor raster: one steppable flag per obstacle");
  Eigen::AlignedBox2d bounds;
  for (const auto* soup : obstacles) {
    if (!soup->bounds.isEmpty()) {
      bounds.extend(Eigen::Vector2d(soup->bounds.min().head<2>()));
      bounds.extend(Eigen::Vector2d(soup->bounds.max().head<2>()));
    }
  }
  if (bounds.isEmpty()) bounds = Eigen::AlignedBox2d(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1));
  origin_ = bounds.min() - Eigen::Vector2d(1.0, 1.0);
  const Eigen::Vector2d size = bounds.sizes() + Eigen::Vector2d(2.0, 2.0);
  const int cols = static_cast<int>(std::ceil(size.x() / resolution_));
  const int rows = static_cast<int>(std::ceil(size.y() / resolution_));
  cv::Mat occupied = cv::Mat::zeros(rows, cols, CV_8U);  // 1 = furniture, 2 = steppable furniture
  // Fixed-point drawing (shift 4) keeps sub-cell precision of the triangle corners.
  constexpr int kShift = 4;
  const double scale = (1 << kShift) / resolution_;
  // Steppable furniture first, so that anything else drawn over it stays a hard obstacle.
  std::vector<std::size_t> order(obstacles.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_partition(order.begin(), order.end(), [&](std::size_t i) { return steppable[i]; });
  for (const std::size_t i : order) {
    const geom::TriangleSoup* soup = obstacles[i];
    const cv::Scalar value(steppable[i] ? 2 : 1);
    for (const auto& t : soup->triangles) {
      cv::Point pts[3];
      const Eigen::Vector3d* v[3] = {&t.a, &t.b, &t.c};
      for (int k = 0; k < 3; ++k) {
        pts[k] = cv::Point(static_cast<int>(std::lround((v[k]->x() - origin_.x()) * scale)),
                           static_cast<int>(std::lround((v[k]->y() - origin_.y()) * scale)));
      }
      cv::fillConvexPoly(occupied, pts, 3, value, cv::LINE_8, kShift);
    }
  }
  // A centre is valid when the robot square around it is clear: dilate the obstacles by it.
  const int half = static_cast<int>(std::lround(options.robot_size / 2.0 / resolution_));
  const cv::Mat square = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * half + 1, 2 * half + 1));
  cv::Mat blocked, hard_blocked;
  cv::dilate(occupied > 0, blocked, square);
  cv::dilate(occupied == 1, hard_blocked, square);
  robot_free_ = 1 - blocked / 255;
  robot_room_ = 1 - hard_blocked / 255;
}

cv::Point2i FloorRaster::cell_of(const geom::Point2& p) const {
  return cv::Point2i(static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_)),
                     static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_)));
}

geom::Point2 FloorRaster::cell_centre(int row, int col) const {
  return origin_ + geom::Point2((col + 0.5) * resolution_, (row + 0.5) * resolution_);
}

namespace {

// A rectangle in a frame at `yaw`: [lo, hi] in that frame's coordinates.
struct Strip {
  double yaw;
  Eigen::Vector2d lo, hi;
  Eigen::Vector2d ideal;  // preferred standing point, in the frame
};

Strip side_strip(Side side, const Eigen::AlignedBox2d& owner_H, const Eigen::AlignedBox2d& plat_H,
                 double yaw, double depth, double robot) {
  Strip s{yaw, {}, {}, {}};
  // The robot centre stays at least half a robot away from the owner's face.
  const double near = robot / 2.0;
  switch (side) {
    case Side::kRear:
      s.lo = {plat_H.min().x(), owner_H.min().y() - depth};
      s.hi = {plat_H.max().x(), owner_H.min().y()};
      s.ideal = {plat_H.center().x(), owner_H.min().y() - near};
      break;
    case Side::kFront:
      s.lo = {plat_H.min().x(), owner_H.max().y()};
      s.hi = {plat_H.max().x(), owner_H.max().y() + depth};
      s.ideal = {plat_H.center().x(), owner_H.max().y() + near};
      break;
    case Side::kLeft:
      s.lo = {owner_H.min().x() - depth, plat_H.min().y()};
      s.hi = {owner_H.min().x(), plat_H.max().y()};
      s.ideal = {owner_H.min().x() - near, plat_H.center().y()};
      break;
    case Side::kRight:
      s.lo = {owner_H.max().x(), plat_H.min().y()};
      s.hi = {owner_H.max().x() + depth, plat_H.max().y()};
      s.ideal = {owner_H.max().x() + near, plat_H.center().y()};
      break;
  }
  return s;
}

// Points of the platform a camera must see: the centroid and four points halfway to its edges.
// They do not depend on where the robot stands, so they are computed once per platform.
std::vector<geom::Point2> visibility_targets(const Platform& platform, const geom::Region& poly_W) {
  const geom::Point2 c = geom::centroid(poly_W);
  const Eigen::Vector2d half = platform.box_P.sizes() / 4.0;
  const Eigen::Rotation2Dd R(platform.X_WP.rotation());
  std::vector<geom::Point2> targets = {c};
  for (const auto& d : {Eigen::Vector2d(half.x(), 0), Eigen::Vector2d(-half.x(), 0),
                        Eigen::Vector2d(0, half.y()), Eigen::Vector2d(0, -half.y())}) {
    targets.push_back(geom::closest_point(poly_W, c + R * d));
  }
  return targets;
}

bool visible_from(const geom::Point2& stand, const Platform& platform, const std::vector<geom::Point2>& targets,
                  const geom::TriangleSoup& occluders, const GraphOptions& options) {
  for (const double above : options.camera_heights_above) {
    const Eigen::Vector3d eye(stand.x(), stand.y(), platform.height + above);
    for (const auto& t : targets) {
      const Eigen::Vector3d target(t.x(), t.y(), platform.height + 0.01);
      // Blocked when something of the owner lies between the eye and the target.
      if (geom::ray_hit(occluders, eye, target - eye, 1e-6, 0.98) < 0.0) return true;
    }
  }
  return false;
}

}  // namespace

void evaluate_sides(Platform& platform, const geom::Ring& owner_footprint, double owner_heading,
                    const geom::TriangleSoup& owner_soup, const FloorRaster& raster,
                    const GraphOptions& options) {
  // Heading frame H: rotation by owner_heading about the world origin.
  const Eigen::Rotation2Dd R_WH(owner_heading);
  const Eigen::Rotation2Dd R_HW = R_WH.inverse();
  const geom::Region poly_W = platform.polygon_W();
  Eigen::AlignedBox2d owner_H, plat_H;
  for (const auto& p : owner_footprint) owner_H.extend(R_HW * p);
  for (const auto& ring : poly_W.rings) {
    for (const auto& p : ring) plat_H.extend(R_HW * p);
  }
  const std::vector<geom::Point2> targets = visibility_targets(platform, poly_W);
  const double cell_area = raster.resolution() * raster.resolution();
  constexpr double kSlice = 0.10;  // m across the side per entry of SideInfo::stands
  for (const Side side : kSides) {
    const Strip strip =
        side_strip(side, owner_H, plat_H, owner_heading, options.standing_depth, options.robot_size);
    // Across the side runs along H's x for the rear and front, along y for the left and right.
    const int across = side == Side::kRear || side == Side::kFront ? 0 : 1;
    const int slices = std::max(1, static_cast<int>(std::ceil((strip.hi[across] - strip.lo[across]) / kSlice)));
    SideInfo info;
    // Scan the raster cells under the strip's world bounding box.
    Eigen::AlignedBox2d box_W;
    for (const auto& corner : {strip.lo, Eigen::Vector2d(strip.hi.x(), strip.lo.y()), strip.hi,
                               Eigen::Vector2d(strip.lo.x(), strip.hi.y())}) {
      info.strip_W.push_back(R_WH * corner);
      box_W.extend(info.strip_W.back());
    }
    const cv::Point2i c0 = raster.cell_of(box_W.min());
    const cv::Point2i c1 = raster.cell_of(box_W.max());
    const geom::Point2 ideal_W = R_WH * strip.ideal;
    // The best cell so far: clear of everything beats clear but for steppable furniture, then
    // nearness to the ideal point (or, per slice, to the ideal line along the face).
    struct Best {
      bool clear = false;
      double d = std::numeric_limits<double>::infinity();
      geom::Point2 at = geom::Point2::Zero();
      bool found = false;
      void offer(bool c, double dist, const geom::Point2& p) {
        if (found && (clear && !c)) return;
        if (found && clear == c && dist >= d) return;
        clear = c;
        d = dist;
        at = p;
        found = true;
      }
    };
    Best point;
    std::vector<Best> per_slice(static_cast<std::size_t>(slices));
    long count = 0;
    for (int row = std::max(0, c0.y); row <= std::min(raster.robot_room().rows - 1, c1.y); ++row) {
      const std::uint8_t* room = raster.robot_room().ptr<std::uint8_t>(row);
      const std::uint8_t* free = raster.robot_free().ptr<std::uint8_t>(row);
      for (int col = std::max(0, c0.x); col <= std::min(raster.robot_room().cols - 1, c1.x); ++col) {
        if (room[col] == 0) continue;
        const geom::Point2 p_W = raster.cell_centre(row, col);
        const Eigen::Vector2d p_H = R_HW * p_W;
        if (p_H.x() < strip.lo.x() || p_H.x() > strip.hi.x() || p_H.y() < strip.lo.y() ||
            p_H.y() > strip.hi.y()) {
          continue;
        }
        ++count;
        const bool clear = free[col] != 0;
        point.offer(clear, (p_W - ideal_W).squaredNorm(), p_W);
        const int k = std::clamp(static_cast<int>((p_H[across] - strip.lo[across]) / kSlice), 0, slices - 1);
        per_slice[static_cast<std::size_t>(k)].offer(clear, std::abs(p_H[1 - across] - strip.ideal[1 - across]), p_W);
      }
    }
    info.standing_area = static_cast<double>(count) * cell_area;
    if (point.found) info.standing_point = point.at;
    for (const Best& b : per_slice) {
      if (b.found) info.stands.push_back(b.at);
    }
    if (count > 0) info.visible = visible_from(info.standing_point, platform, targets, owner_soup, options);
    platform.sides[static_cast<std::size_t>(side)] = info;
  }
  platform.default_side = arrival_side(platform);
}

int arrival_side(const Platform& platform) {
  int best = -1;
  for (const Side side : kSides) {
    const SideInfo& info = platform.sides[static_cast<std::size_t>(side)];
    if (!info.usable()) continue;
    if (best >= 0) {
      const SideInfo& b = platform.sides[static_cast<std::size_t>(best)];
      if (info.objects_seen != b.objects_seen) {
        if (info.objects_seen < b.objects_seen) continue;
      } else if (info.sight_lines != b.sight_lines) {
        if (info.sight_lines < b.sight_lines) continue;
      } else if (info.standing_area <= b.standing_area + 1e-9) {
        continue;
      }
    }
    best = static_cast<int>(side);
  }
  return best;
}

double eye_height(const Platform& platform, double platform_height, double tallest_top) {
  double eye_z = std::max(platform_height + 0.6, tallest_top + 0.35);
  if (std::isfinite(platform.clearance)) {
    eye_z = std::min(eye_z, platform_height + std::max(0.06, platform.clearance - 0.04));
  }
  return eye_z;
}

}  // namespace mtg::graph
