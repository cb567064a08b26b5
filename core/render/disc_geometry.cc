#include "core/render/disc_geometry.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace mtg::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

bool segments_cross(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, const Eigen::Vector2d& q1,
                    const Eigen::Vector2d& q2) {
  if ((p1 - p2).norm() < 0.5 || (q1 - q2).norm() < 0.5) return false;  // a disc on its anchor: no line
  const double d1 = cross(p2 - p1, q1 - p1), d2 = cross(p2 - p1, q2 - p1);
  const double d3 = cross(q2 - q1, p1 - q1), d4 = cross(q2 - q1, p2 - q1);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0;
}

double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 < 1e-12) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

std::vector<Eigen::Vector2d> disc_candidates(const Eigen::Vector2d& anchor, double r) {
  static const std::array<double, 6> kRings = {2.0, 2.8, 3.8, 5.0, 6.5, 8.5};
  static const std::array<int, 16> kOrder = {0, 1, 15, 2, 14, 3, 13, 4, 12, 5, 11, 6, 10, 7, 9, 8};
  std::vector<Eigen::Vector2d> out;
  for (const double ring : kRings) {
    for (const int k : kOrder) {
      const double angle = -kPi / 2 + 2 * kPi * k / 16.0;
      out.push_back(anchor + ring * r * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
  }
  return out;
}

}  // namespace mtg::render
