#include "core/geom/polygon.h"

#include <clipper.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mtg::geom {
namespace cl = ClipperLib;
namespace {

constexpr double kScale = 1e6;  // 1 µm resolution in Clipper's integer space

// std::llround (halves away from zero) without the library call: a conversion truncates toward
// zero, and below 2^52 the fraction left is exact, so the comparison with a half rounds as
// llround does, to the bit. Anything larger (or not a number) goes to llround itself.
cl::cInt round_to_int(double v) {
  if (!(std::abs(v) < 0x1p52)) return static_cast<cl::cInt>(std::llround(v));
  const auto t = static_cast<cl::cInt>(v);
  const double fraction = v - static_cast<double>(t);
  return fraction >= 0.5 ? t + 1 : (fraction <= -0.5 ? t - 1 : t);
}
cl::IntPoint to_int(const Point2& p) { return cl::IntPoint(round_to_int(p.x() * kScale), round_to_int(p.y() * kScale)); }
Point2 to_double(const cl::IntPoint& p) {
  return Point2(static_cast<double>(p.X) / kScale, static_cast<double>(p.Y) / kScale);
}
cl::Path to_path(const Ring& ring) {
  cl::Path path;
  path.reserve(ring.size());
  for (const auto& p : ring) path.push_back(to_int(p));
  return path;
}
cl::Paths to_paths(const Region& r) {
  cl::Paths paths;
  paths.reserve(r.rings.size());
  for (const auto& ring : r.rings) paths.push_back(to_path(ring));
  return paths;
}
Region to_region(const cl::Paths& paths) {
  Region r;
  for (const auto& path : paths) {
    if (path.size() < 3) continue;
    Ring ring;
    ring.reserve(path.size());
    for (const auto& p : path) ring.push_back(to_double(p));
    r.rings.push_back(std::move(ring));
  }
  return r;
}
// Clipper's result orientation follows the fill rule; we normalise through a union so that
// outer rings are counter-clockwise and holes clockwise.
Region execute(cl::ClipType type, const cl::Paths& subject, const cl::Paths& clip) {
  cl::Clipper c;
  c.AddPaths(subject, cl::ptSubject, true);
  if (!clip.empty()) c.AddPaths(clip, cl::ptClip, true);
  cl::Paths out;
  c.Execute(type, out, cl::pftNonZero, cl::pftNonZero);
  return to_region(out);
}

// The rings of `r` whose boxes meet `box`. A ring wholly outside the box of the other operand of
// an intersection winds zero times around every point of the result (its box holds none of
// them): leaving it out gives the same point set from less work (resolving a placement target
// intersects a platform's free space, with a hole per object, with one small rectangle).
// Clipper's rounding is not quite blind to it: every vertex bounds a scanbeam, where Clipper
// snaps intersection points, so a vertex of the result may land 1 µm (its grid) from where the
// full input would have put it. Either is as exact as Clipper is; what matters is that the
// same input always gives the same output, which it does. The three shipped apartments'
// task sets came out the same bytes with and without it.
cl::Paths paths_meeting(const Region& r, const std::vector<Eigen::AlignedBox2d>& ring_boxes,
                        const Eigen::AlignedBox2d& box) {
  cl::Paths paths;
  paths.reserve(r.rings.size());
  for (std::size_t k = 0; k < r.rings.size(); ++k) {
    if (ring_boxes[k].intersects(box)) paths.push_back(to_path(r.rings[k]));
  }
  return paths;
}

// Each ring's box, and the region's (their union).
Eigen::AlignedBox2d ring_bounds(const Region& r, std::vector<Eigen::AlignedBox2d>& ring_boxes) {
  Eigen::AlignedBox2d all;
  ring_boxes.clear();
  for (const auto& ring : r.rings) {
    ring_boxes.push_back(bounds(ring));
    all.extend(ring_boxes.back());
  }
  return all;
}

// Relative to the product of the two edges' lengths: the sine of the angle below which a turn
// is not trusted to be a turn, and below which two edges count as parallel. Doubles round at
// about 1e-16 of a value; these leave a wide margin.
constexpr double kTurnTolerance = 1e-9;
constexpr double kParallelTolerance = 1e-6;

double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

}  // namespace

Point2 closest_on_segment(const Point2& a, const Point2& b, const Point2& p) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

double signed_area(const Ring& ring) {
  double a = 0.0;
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
    const Point2& p = ring[i];
    const Point2& q = ring[(i + 1) % n];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

double area(const Region& region) {
  double a = 0.0;
  for (const auto& ring : region.rings) a += signed_area(ring);
  return a;
}

Region rectangle(const Point2& min, const Point2& max) {
  if (!(max.x() > min.x() && max.y() > min.y())) return {};
  return Region{{Ring{min, Point2(max.x(), min.y()), max, Point2(min.x(), max.y())}}};
}

Region from_ring(const Ring& ring) {
  if (ring.size() < 3) return {};
  return unite_rings({ring});  // it orients the ring
}

Ring mirrored(const Ring& ring) {
  Ring out;
  out.reserve(ring.size());
  for (const auto& q : ring) out.push_back(-q);
  return out;
}

Region unite_rings(const std::vector<Ring>& rings) {
  cl::Paths paths;
  paths.reserve(rings.size());
  for (const auto& ring : rings) {
    cl::Path path = to_path(ring);
    if (!cl::Orientation(path)) cl::ReversePath(path);  // every ring is a filled polygon
    paths.push_back(std::move(path));
  }
  return execute(cl::ctUnion, paths, {});
}

Region unite(const Region& a, const Region& b) {
  return execute(cl::ctUnion, to_paths(a), to_paths(b));
}
Region intersect(const Region& a, const Region& b) {
  if (a.empty() || b.empty()) return {};
  std::vector<Eigen::AlignedBox2d> boxes_a, boxes_b;
  const Eigen::AlignedBox2d box_a = ring_bounds(a, boxes_a), box_b = ring_bounds(b, boxes_b);
  if (!box_a.intersects(box_b)) return {};
  return execute(cl::ctIntersection, paths_meeting(a, boxes_a, box_b), paths_meeting(b, boxes_b, box_a));
}
Region subtract(const Region& a, const Region& b) {
  if (a.empty()) return {};
  if (b.empty()) return a;
  return execute(cl::ctDifference, to_paths(a), to_paths(b));
}

Region offset(const Region& region, double delta) {
  cl::ClipperOffset co(4.0);
  co.AddPaths(to_paths(region), cl::jtMiter, cl::etClosedPolygon);
  cl::Paths out;
  co.Execute(out, delta * kScale);
  // ClipperOffset ends with a union of its own (outer rings counter-clockwise, holes clockwise,
  // shrinking too: it unites with a frame and drops the frame), so its rings are used as they
  // come; another union cost a tenth of task generation's Clipper time and changed no task.
  return to_region(out);
}

namespace {

// ∂A ⊕ pattern for a convex pattern: the union of the hulls swept by the pattern along each
// boundary edge (the hull of its two translates). Clipper's own closed-path MinkowskiSum fills
// the interior for some vertex orders, so the band is built from these convex pieces instead.
cl::Paths boundary_band(const Region& a, const Ring& convex_pattern) {
  std::vector<Ring> pieces;
  for (const auto& ring : a.rings) {
    for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
      std::vector<Point2> pts;
      pts.reserve(2 * convex_pattern.size());
      for (const auto& q : convex_pattern) {
        pts.push_back(ring[i] + q);
        pts.push_back(ring[(i + 1) % n] + q);
      }
      pieces.push_back(convex_hull(std::move(pts)));
    }
  }
  cl::Paths paths;
  for (const auto& piece : pieces) {
    if (piece.size() >= 3) paths.push_back(to_path(piece));
  }
  return paths;
}

}  // namespace

Region dilate(const Region& a, const Ring& convex_pattern) {
  if (a.empty() || convex_pattern.empty()) return {};
  // A ⊕ B = (A + b0) ∪ (∂A ⊕ B) for a connected B: one translate plus the boundary band.
  cl::Paths shifted = to_paths(a);
  const cl::IntPoint b0 = to_int(convex_pattern.front());
  for (auto& path : shifted) {
    for (auto& p : path) {
      p.X += b0.X;
      p.Y += b0.Y;
    }
  }
  return execute(cl::ctUnion, shifted, boundary_band(a, convex_pattern));
}

Region erode(const Region& a, const Ring& convex_pattern) {
  if (a.empty() || convex_pattern.empty()) return {};
  const Ring minus_b = mirrored(convex_pattern);
  if (contains(from_ring(convex_pattern), Point2::Zero())) {
    // For a convex B holding its reference point: p + B ⊆ A  <=>  p ∈ A and p ∉ ∂A ⊕ (-B)
    // (a path from p into B that leaves A crosses its boundary). The band around the boundary
    // is one Minkowski sum of the rings, much cheaper than dilating A's complement.
    return execute(cl::ctDifference, to_paths(a), boundary_band(a, minus_b));
  }
  // General case: p + B ⊆ A  <=>  p ∉ (complement(A) ⊕ (-B)).
  Eigen::AlignedBox2d box = bounds(a);
  double reach = 0.0;
  for (const auto& q : convex_pattern) reach = std::max(reach, q.norm());
  box.min() -= Eigen::Vector2d::Constant(2.0 * reach + 1.0);
  box.max() += Eigen::Vector2d::Constant(2.0 * reach + 1.0);
  const Region outside = subtract(rectangle(box.min(), box.max()), a);
  return subtract(a, dilate(outside, minus_b));
}

Region clean(const Region& region, double min_area, double tolerance) {
  cl::Paths paths = to_paths(region);
  cl::CleanPolygons(paths, tolerance * kScale);
  Region cleaned = execute(cl::ctUnion, paths, {});
  Region out;
  for (const Region& piece : components(cleaned)) {
    if (area(piece) >= min_area) {
      out.rings.insert(out.rings.end(), piece.rings.begin(), piece.rings.end());
    }
  }
  return out;
}

bool contains(const Region& region, const Point2& p) {
  const cl::IntPoint q = to_int(p);
  int winding = 0;
  for (const auto& ring : region.rings) {
    const cl::Path path = to_path(ring);
    const int inside = cl::PointInPolygon(q, path);  // 0 outside, 1 inside, -1 on boundary
    if (inside == -1) return true;
    if (inside == 1) winding += cl::Orientation(path) ? 1 : -1;
  }
  return winding > 0;
}

std::vector<Region> components(const Region& region) {
  cl::Clipper c;
  c.AddPaths(to_paths(region), cl::ptSubject, true);
  cl::PolyTree tree;
  c.Execute(cl::ctUnion, tree, cl::pftNonZero, cl::pftNonZero);
  std::vector<Region> out;
  // Outer rings are the even-depth nodes; their children are holes, grandchildren new outers.
  std::vector<const cl::PolyNode*> stack;
  for (const cl::PolyNode* child : tree.Childs) stack.push_back(child);
  for (std::size_t i = 0; i < stack.size(); ++i) {
    const cl::PolyNode* outer = stack[i];
    cl::Paths piece{outer->Contour};
    for (const cl::PolyNode* hole : outer->Childs) {
      piece.push_back(hole->Contour);
      for (const cl::PolyNode* inner : hole->Childs) stack.push_back(inner);
    }
    out.push_back(to_region(piece));
  }
  return out;
}

Point2 closest_point(const Region& region, const Point2& p) {
  if (contains(region, p)) return p;
  Point2 best = p;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& ring : region.rings) {
    for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
      const Point2 q = closest_on_segment(ring[i], ring[(i + 1) % n], p);
      const double d = (q - p).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = q;
      }
    }
  }
  return best;
}

double distance_to_boundary(const Region& region, const Point2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& ring : region.rings) {
    for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
      best = std::min(best, (closest_on_segment(ring[i], ring[(i + 1) % n], p) - p).norm());
    }
  }
  return best;
}

Point2 centroid(const Region& region) {
  double a = 0.0;
  Point2 c = Point2::Zero();
  for (const auto& ring : region.rings) {
    for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
      const Point2& p = ring[i];
      const Point2& q = ring[(i + 1) % n];
      const double w = p.x() * q.y() - q.x() * p.y();
      a += w;
      c += (p + q) * w;
    }
  }
  if (std::abs(a) < 1e-18) {
    const auto b = bounds(region);
    return b.isEmpty() ? Point2::Zero() : Point2(b.center());
  }
  return c / (3.0 * a);
}

Eigen::AlignedBox2d bounds(const Ring& ring) {
  Eigen::AlignedBox2d b;
  for (const auto& p : ring) b.extend(p);
  return b;
}

Eigen::AlignedBox2d bounds(const Region& region) {
  Eigen::AlignedBox2d b;
  for (const auto& ring : region.rings) b.extend(bounds(ring));
  return b;
}

namespace {

// A type, not a function, so that sort and merge inline it.
struct LexicographicLess {
  bool operator()(const Point2& a, const Point2& b) const { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); }
};
constexpr LexicographicLess lexicographic_less;

// Andrew's monotone chain over points in lexicographic order: lower then upper chain,
// counter-clockwise.
Ring hull_of_sorted(std::vector<Point2>& pts) {
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  Ring hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  hull.resize(k - 1);
  // Start from the lowest-then-leftmost point for a canonical ring.
  const auto start = std::min_element(hull.begin(), hull.end(), [](const Point2& a, const Point2& b) {
    return a.y() < b.y() || (a.y() == b.y() && a.x() < b.x());
  });
  std::rotate(hull.begin(), start, hull.end());
  return hull;
}

}  // namespace

Ring convex_hull(std::vector<Point2> pts) {
  std::sort(pts.begin(), pts.end(), lexicographic_less);
  return hull_of_sorted(pts);
}

namespace {

// convex_hull of every a_i + b_j, from all of them.
Ring hull_of_all_sums(const Ring& a, const Ring& b) {
  // The sums come as one run per point of a, each b's points in order plus that point. Adding a
  // point keeps the order except where rounding ties two sums in x (insertion puts those right,
  // moving little); merging the runs then gives the order a sort of all the sums gives, which is
  // unique up to equal points, and those are dropped. So the hull is convex_hull's, bit for bit,
  // except that of two sums equal but for the sign of a zero coordinate another may be kept
  // (both round to the same Clipper point, the only use of a Minkowski sum).
  std::vector<Point2> bs(b.begin(), b.end());
  std::sort(bs.begin(), bs.end(), lexicographic_less);
  const std::size_t m = bs.size(), total = a.size() * m;
  std::vector<Point2> pts(total), merged(total);
  for (std::size_t i = 0; i < a.size(); ++i) {
    Point2* run = pts.data() + i * m;
    for (std::size_t j = 0; j < m; ++j) run[j] = a[i] + bs[j];
    for (std::size_t j = 1; j < m; ++j) {
      for (std::size_t k = j; k > 0 && lexicographic_less(run[k], run[k - 1]); --k) std::swap(run[k], run[k - 1]);
    }
  }
  for (std::size_t width = m; width < total; width *= 2) {
    for (std::size_t lo = 0; lo < total; lo += 2 * width) {
      const std::size_t mid = std::min(lo + width, total), hi = std::min(lo + 2 * width, total);
      std::merge(pts.begin() + static_cast<std::ptrdiff_t>(lo), pts.begin() + static_cast<std::ptrdiff_t>(mid),
                 pts.begin() + static_cast<std::ptrdiff_t>(mid), pts.begin() + static_cast<std::ptrdiff_t>(hi),
                 merged.begin() + static_cast<std::ptrdiff_t>(lo), lexicographic_less);
    }
    std::swap(pts, merged);
  }
  return hull_of_sorted(pts);
}

// Whether `ring` is convex and counter-clockwise, going round once, with no edge of zero length:
// what the merge below needs. A turn to the right is allowed only within rounding (a hull turned
// into another frame), never a turn back (a spike out and back along one line), and going round
// once means the edges' x and y directions each change sign twice at most.
bool convex_once_round(const Ring& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const Point2& p = ring[(i + n - 1) % n];
    const Point2& q = ring[i];
    const Point2& r = ring[(i + 1) % n];
    const double lengths = (q - p).norm() * (r - q).norm(), turn = cross(p, q, r);
    if (!(lengths > 0.0) || turn < -kTurnTolerance * lengths) return false;
    if ((q - p).dot(r - q) <= 0.0 && std::abs(turn) <= kParallelTolerance * lengths) return false;
  }
  // Sign changes of one coordinate of the edges, round the ring (edges flat in it skipped).
  const auto sign_changes = [&](int axis) {
    int changes = 0, first = 0, last = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = ring[(i + 1) % n][axis] - ring[i][axis];
      const int sign = (d > 0) - (d < 0);
      if (sign == 0) continue;
      if (last != 0 && sign != last) ++changes;
      if (first == 0) first = sign;
      last = sign;
    }
    return changes + (first != 0 && last != first ? 1 : 0);
  };
  return sign_changes(0) <= 2 && sign_changes(1) <= 2;
}

}  // namespace

Ring convex_hull_of_sums(const Ring& a, const Ring& b) {
  if (a.empty() || b.empty()) return {};
  if (!convex_once_round(a) || !convex_once_round(b)) return hull_of_all_sums(a, b);
  // The sum of two convex rings is walked by merging their edges in the order of their
  // directions, from the two lowest-then-leftmost vertices: n + m sums instead of n * m. Where
  // two edges are nearly parallel both of the sums between them are kept, so every sum that can
  // be a vertex is among the candidates; the hull of the candidates is then the hull of all sums
  // (a test compares them bit for bit).
  const auto lowest = [](const Ring& r) {
    return static_cast<std::size_t>(std::min_element(r.begin(), r.end(), [](const Point2& p, const Point2& q) {
                                      return p.y() < q.y() || (p.y() == q.y() && p.x() < q.x());
                                    }) - r.begin());
  };
  const std::size_t n = a.size(), m = b.size(), ia = lowest(a), ib = lowest(b);
  const auto A = [&](std::size_t i) -> const Point2& { return a[(ia + i) % n]; };
  const auto B = [&](std::size_t j) -> const Point2& { return b[(ib + j) % m]; };
  std::vector<Point2> pts;
  pts.reserve(2 * (n + m));
  std::size_t i = 0, j = 0;
  while (i < n || j < m) {
    pts.push_back(A(i) + B(j));
    if (i == n) { ++j; continue; }
    if (j == m) { ++i; continue; }
    const Point2 ea = A(i + 1) - A(i), eb = B(j + 1) - B(j);
    const double turn = ea.x() * eb.y() - ea.y() * eb.x();
    if (std::abs(turn) <= kParallelTolerance * ea.norm() * eb.norm()) {
      pts.push_back(A(i + 1) + B(j));
      pts.push_back(A(i) + B(j + 1));
      ++i;
      ++j;
    } else if (turn > 0) {
      ++i;  // a's edge turns less: it comes first
    } else {
      ++j;
    }
  }
  std::sort(pts.begin(), pts.end(), lexicographic_less);
  return hull_of_sorted(pts);
}

double wrap_angle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0.0) a += 2.0 * M_PI;
  return a - M_PI;
}

OrientedBox min_area_rect(const Ring& hull, double preferred_yaw) {
  OrientedBox best;
  if (hull.empty()) return best;
  if (hull.size() < 3) {
    const auto b = bounds(hull);
    best.centre = b.center();
    best.half = b.sizes() / 2.0;
    best.yaw = 0.0;
    return best;
  }
  double best_area = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, n = hull.size(); i < n; ++i) {
    const Eigen::Vector2d e = hull[(i + 1) % n] - hull[i];
    if (e.norm() < 1e-12) continue;
    const double yaw = std::atan2(e.y(), e.x());
    const Eigen::Rotation2Dd R(-yaw);
    Eigen::AlignedBox2d b;
    for (const auto& p : hull) b.extend(R * p);
    const double a = b.volume();
    if (a < best_area - 1e-12) {
      best_area = a;
      best.yaw = yaw;
      best.half = b.sizes() / 2.0;
      best.centre = Eigen::Rotation2Dd(yaw) * b.center();
    }
  }
  // Canonical axis: the quarter turn of the optimal rectangle nearest the preferred yaw.
  double chosen = best.yaw;
  double chosen_diff = std::numeric_limits<double>::infinity();
  Eigen::Vector2d half = best.half;
  for (int k = 0; k < 4; ++k) {
    const double candidate = wrap_angle(best.yaw + k * M_PI / 2.0);
    const double diff = std::abs(wrap_angle(candidate - preferred_yaw));
    if (diff < chosen_diff - 1e-9 || (std::abs(diff - chosen_diff) <= 1e-9 && candidate < chosen)) {
      chosen_diff = diff;
      chosen = candidate;
      half = (k % 2 == 0) ? best.half : Eigen::Vector2d(best.half.y(), best.half.x());
    }
  }
  best.yaw = chosen;
  best.half = half;
  return best;
}

Ring transform(const Ring& ring, const Eigen::Isometry2d& X) {
  Ring out;
  out.reserve(ring.size());
  for (const auto& p : ring) out.push_back(X * p);
  return out;
}

Region transform(const Region& region, const Eigen::Isometry2d& X) {
  Region out;
  for (const auto& ring : region.rings) out.rings.push_back(transform(ring, X));
  return out;
}

}  // namespace mtg::geom
