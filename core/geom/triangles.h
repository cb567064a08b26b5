#pragma once
// World-space triangle soups, the input of surface detection, visibility and rasterisation.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace mtg::geom {

struct Triangle {
  Eigen::Vector3d a, b, c;
  Eigen::Vector3d normal() const;  // unit, zero for degenerate triangles
};

struct TriangleSoup {
  std::vector<Triangle> triangles;
  Eigen::AlignedBox3d bounds;
  void add(const Triangle& t);
  bool empty() const { return triangles.empty(); }
};

/// Nearest hit distance along the ray origin + t·dir (dir need not be unit) with t in
/// (t_min, t_max), or a negative value when nothing is hit (Möller–Trumbore, both faces).
double ray_hit(const TriangleSoup& soup, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
               double t_min, double t_max);

/// Whether anything of `soup` lies on the ray within (t_min, t_max): ray_hit >= 0, stopping at
/// the first triangle hit.
bool ray_blocked(const TriangleSoup& soup, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_min,
                 double t_max);

}  // namespace mtg::geom
