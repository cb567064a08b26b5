#include "core/geom/triangles.h"

#include <cmath>
#include <limits>

namespace mtg::geom {

Eigen::Vector3d Triangle::normal() const {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double len = n.norm();
  return len > 1e-15 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

void TriangleSoup::add(const Triangle& t) {
  triangles.push_back(t);
  bounds.extend(t.a);
  bounds.extend(t.b);
  bounds.extend(t.c);
}

namespace {

// Slab test against the soup's bounds: most rays miss most objects.
bool may_hit(const TriangleSoup& soup, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_min,
             double t_max) {
  if (soup.bounds.isEmpty()) return false;
  double lo = t_min, hi = t_max;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir[k]) < 1e-15) {
      if (origin[k] < soup.bounds.min()[k] || origin[k] > soup.bounds.max()[k]) return false;
      continue;
    }
    double t0 = (soup.bounds.min()[k] - origin[k]) / dir[k];
    double t1 = (soup.bounds.max()[k] - origin[k]) / dir[k];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
    if (lo > hi) return false;
  }
  return true;
}

// Möller–Trumbore, both faces: the ray parameter of the hit, or NaN when the ray misses.
double hit_distance(const Triangle& tri, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  constexpr double kMiss = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d e1 = tri.b - tri.a;
  const Eigen::Vector3d e2 = tri.c - tri.a;
  const Eigen::Vector3d p = dir.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-15) return kMiss;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = origin - tri.a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0) return kMiss;
  const Eigen::Vector3d q = s.cross(e1);
  const double v = dir.dot(q) * inv;
  if (v < 0.0 || u + v > 1.0) return kMiss;
  return e2.dot(q) * inv;
}

}  // namespace

double ray_hit(const TriangleSoup& soup, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
               double t_min, double t_max) {
  if (!may_hit(soup, origin, dir, t_min, t_max)) return -1.0;
  double best = -1.0;
  double limit = t_max;
  for (const Triangle& tri : soup.triangles) {
    const double t = hit_distance(tri, origin, dir);
    if (t > t_min && t < limit) {
      limit = t;
      best = t;
    }
  }
  return best;
}

bool ray_blocked(const TriangleSoup& soup, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_min,
                 double t_max) {
  if (!may_hit(soup, origin, dir, t_min, t_max)) return false;
  for (const Triangle& tri : soup.triangles) {
    const double t = hit_distance(tri, origin, dir);
    if (t > t_min && t < t_max) return true;
  }
  return false;
}

}  // namespace mtg::geom
