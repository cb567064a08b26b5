#include "core/graph/platforms.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mtg::graph {
namespace {

constexpr double kBelowBox = 0.10;  // a surface may lie this far under a receptacle box
constexpr double kAboveBox = 0.03;  // ... or this far above its bottom
constexpr double kMinSelectOverlap = 0.25;  // of the smaller of box footprint and surface

// The receptacle box in world coordinates (an AABB of its 8 transformed corners: the boxes are
// axis-aligned in their object's frame, and objects stand upright, so this is tight in z).
Eigen::AlignedBox3d receptacle_box_W(const Eigen::Isometry3d& X_WO,
                                     const scene::DeclaredReceptacle& r, geom::Ring& footprint) {
  Eigen::AlignedBox3d box;
  std::vector<geom::Point2> xy;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p =
        X_WO * (r.T_OR * r.box_R.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c)));
    box.extend(p);
    xy.emplace_back(p.head<2>());
  }
  footprint = geom::convex_hull(std::move(xy));
  return box;
}

bool passes_size_filters(const Surface& s, double largest, const GraphOptions& options) {
  return s.area >= options.min_platform_area &&
         s.area >= options.relative_platform_area * largest &&
         s.height <= options.max_platform_height &&
         min_width(s.region) >= options.min_platform_width;
}

}  // namespace

double min_width(const geom::Region& region) {
  std::vector<geom::Point2> pts;
  for (const auto& ring : region.rings) pts.insert(pts.end(), ring.begin(), ring.end());
  const geom::Ring hull = geom::convex_hull(std::move(pts));
  if (hull.size() < 3) return 0.0;
  const geom::OrientedBox box = geom::min_area_rect(hull);
  return 2.0 * std::min(box.half.x(), box.half.y());
}

SurfaceOptions surface_options(const GraphOptions& options) {
  SurfaceOptions so;
  so.max_angle_deg = options.seed_angle_deg;
  so.height_tolerance = options.surface_height_tolerance;
  so.min_area = options.min_platform_area;
  return so;
}

std::vector<PlatformCandidate> platform_candidates(const scene::ObjectInstance& object,
                                                   const Eigen::Isometry3d& X_WO,
                                                   const ObjectGeometry& geometry,
                                                   const GraphOptions& options,
                                                   std::vector<std::string>& warnings) {
  std::vector<PlatformCandidate> out;
  if (!geometry.has_geometry()) return out;
  const std::vector<Surface> surfaces = detect_surfaces(geometry.soup, true, surface_options(options));
  double largest = 0.0;
  for (const auto& s : surfaces) largest = std::max(largest, s.area);

  if (object.receptacles.empty()) {
    for (const auto& s : surfaces) {
      if (passes_size_filters(s, largest, options)) out.push_back({s, "mesh", true});
    }
    return out;
  }

  // Declared receptacles select surfaces; several may select the same one.
  std::map<std::size_t, std::vector<std::string>> selected;  // surface index -> receptacle keys
  for (const scene::DeclaredReceptacle& r : object.receptacles) {
    if (object.parts.at(static_cast<std::size_t>(r.part)).movable_link) continue;  // closed
    geom::Ring footprint;
    const Eigen::AlignedBox3d box = receptacle_box_W(X_WO, r, footprint);
    const geom::Region box_xy = geom::from_ring(footprint);
    const double box_area = geom::area(box_xy);
    if (box_area < 1e-6) {
      warnings.push_back("receptacle " + r.name + " of " + object.name +
                         " has zero area; skipped");
      continue;
    }
    int best = -1;
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
      const Surface& s = surfaces[i];
      if (s.height < box.min().z() - kBelowBox || s.height > box.min().z() + kAboveBox) continue;
      const double overlap = geom::area(geom::intersect(box_xy, s.region));
      if (overlap < kMinSelectOverlap * std::min(box_area, s.area)) continue;
      if (best < 0 || s.height > surfaces[static_cast<std::size_t>(best)].height) {
        best = static_cast<int>(i);
      }
    }
    if (best < 0) {
      char buf[96];
      std::snprintf(buf, sizeof(buf), "%.3f", box.min().z());
      warnings.push_back("receptacle " + r.name + " of " + object.name +
                         ": no supporting surface in the mesh near z = " + buf + " m; skipped");
      continue;
    }
    selected[static_cast<std::size_t>(best)].push_back(r.name);
  }
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    const auto it = selected.find(i);
    if (it != selected.end()) {
      std::string source = "receptacle:";
      for (std::size_t k = 0; k < it->second.size(); ++k) {
        source += (k ? "," : "") + it->second[k];
      }
      out.push_back({surfaces[i], source, true});
    } else if (passes_size_filters(surfaces[i], largest, options)) {
      out.push_back({surfaces[i], "mesh:supports-item", false});
    }
  }
  return out;
}

}  // namespace mtg::graph
