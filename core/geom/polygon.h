#pragma once
// Planar regions and the 2-D operations the scene graph needs. Booleans, offsets and Minkowski
// sums are Clipper's (integer coordinates at 1 µm); hulls and rectangles are small closed forms.
// Units: metres. Frames are whatever the caller's points are in.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace mtg::geom {

using Point2 = Eigen::Vector2d;
/// A closed ring without a repeated end point.
using Ring = std::vector<Point2>;

/// A planar region as rings with Clipper's orientation convention: outer boundaries
/// counter-clockwise, holes clockwise (non-zero fill). Value type; empty() means no area.
struct Region {
  std::vector<Ring> rings;
  bool empty() const { return rings.empty(); }
};

/// Signed area of a ring (> 0 counter-clockwise).
double signed_area(const Ring& ring);
/// Area of a region (holes subtracted).
double area(const Region& region);

/// Axis-aligned rectangle [min, max].
Region rectangle(const Point2& min, const Point2& max);
/// A region from one simple ring of either orientation.
Region from_ring(const Ring& ring);
/// The ring reflected through its reference point (-q for every q): turns "the pattern at p
/// overlaps X" into "p lies in X ⊕ mirrored(pattern)".
Ring mirrored(const Ring& ring);
/// Union of rings of any orientation (each ring taken as a filled polygon).
Region unite_rings(const std::vector<Ring>& rings);

Region unite(const Region& a, const Region& b);
Region intersect(const Region& a, const Region& b);
Region subtract(const Region& a, const Region& b);
/// Grows (delta > 0) or shrinks (delta < 0) the boundary by |delta| with mitred corners.
Region offset(const Region& region, double delta);
/// a ⊕ pattern, for a convex `pattern` given relative to its reference point.
Region dilate(const Region& a, const Ring& convex_pattern);
/// a ⊖ pattern = { p : p + pattern ⊆ a }, for a convex pattern relative to its reference point.
Region erode(const Region& a, const Ring& convex_pattern);
/// Drops pieces smaller than min_area and vertices closer than tolerance.
Region clean(const Region& region, double min_area, double tolerance = 1e-5);

/// True when p lies inside or on the boundary.
bool contains(const Region& region, const Point2& p);
/// Each connected piece (one outer ring with its holes).
std::vector<Region> components(const Region& region);
/// The point of segment ab nearest to p.
Point2 closest_on_segment(const Point2& a, const Point2& b, const Point2& p);
/// The point of the region nearest to p (p itself when inside). Requires a non-empty region.
Point2 closest_point(const Region& region, const Point2& p);
/// Distance from p to the nearest edge of the region (+inf for an empty region).
double distance_to_boundary(const Region& region, const Point2& p);
/// Area centroid of the region.
Point2 centroid(const Region& region);

Eigen::AlignedBox2d bounds(const Ring& ring);
Eigen::AlignedBox2d bounds(const Region& region);

/// Convex hull, counter-clockwise, starting from the lowest-then-leftmost point.
Ring convex_hull(std::vector<Point2> points);
/// convex_hull of every a_i + b_j (the Minkowski sum of two convex rings), the same ring (up to
/// the sign of a zero coordinate), without sorting all a.size() * b.size() points at once.
Ring convex_hull_of_sums(const Ring& a, const Ring& b);

/// A rectangle of half extents `half` centred at `centre`, its x axis at angle `yaw`.
struct OrientedBox {
  Point2 centre = Point2::Zero();
  double yaw = 0.0;
  Eigen::Vector2d half = Eigen::Vector2d::Zero();
};

/// The minimum-area enclosing rectangle of a convex hull (rotating calipers over hull edges).
/// Its yaw is canonical: of the four axis choices of the optimal rectangle, the one nearest
/// to `preferred_yaw` (ties: the smaller angle), so the result never flips between runs.
OrientedBox min_area_rect(const Ring& hull, double preferred_yaw = 0.0);

Ring transform(const Ring& ring, const Eigen::Isometry2d& X);
Region transform(const Region& region, const Eigen::Isometry2d& X);
/// Wraps an angle to (-pi, pi].
double wrap_angle(double a);

}  // namespace mtg::geom
