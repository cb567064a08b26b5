#include "core/render/marks.h"

#include <string>

#include "core/episode/placement.h"

namespace mtg::render {
namespace {

// A point inside `region` near its centroid (the centroid of an L-shaped region may be outside).
geom::Point2 inner_point(const geom::Region& region) {
  const geom::Point2 c = geom::centroid(region);
  return geom::contains(region, c) ? c : geom::closest_point(region, c);
}

}  // namespace

std::vector<ItemMark> item_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform) {
  std::vector<ItemMark> out;
  const std::vector<graph::ObjectId> items = episode::numbered_on(g, s, platform);
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (!items[k].valid()) continue;  // a retired number
    const episode::ObjectState& o = s.objects[items[k]];
    const geom::Point2 c = episode::footprint_centre(o);
    out.push_back({static_cast<int>(k) + 1, items[k], Eigen::Vector3d(c.x(), c.y(), o.top)});
  }
  return out;
}

std::vector<RegionMark> target_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                     graph::Side side, double min_region_size) {
  return target_marks(g, s, platform, episode::place_targets(g, s, platform, side, min_region_size));
}

std::vector<RegionMark> target_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                     const std::vector<episode::PlaceTarget>& targets) {
  std::vector<RegionMark> out;
  const Eigen::Isometry2d X_WP = episode::platform_frame(g, s, platform);
  // Drawn a hair above the surface so the overlay's depth order is never in doubt.
  const double z = episode::platform_height(g, s, platform) + 0.002;
  for (const episode::PlaceTarget& t : targets) {
    if (t.kind == episode::PlaceTarget::Kind::kAnywhere || t.region_P.empty()) continue;
    RegionMark m;
    m.number = std::stoi(t.key);
    const geom::Region region_W = geom::transform(t.region_P, X_WP);
    for (const geom::Ring& ring : region_W.rings) {
      std::vector<Eigen::Vector3d> ring3;
      for (const auto& p : ring) ring3.emplace_back(p.x(), p.y(), z);
      m.rings_W.push_back(std::move(ring3));
    }
    const geom::Point2 c = inner_point(region_W);
    m.label_W = Eigen::Vector3d(c.x(), c.y(), z);
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<LabelMark> fixture_marks(const graph::SceneGraph& g, const episode::WorldState& s, graph::PlatformId platform,
                                     const std::vector<episode::PlaceTarget>& targets) {
  const std::vector<graph::ObjectId> lettered = episode::lettered_anchors(targets, episode::numbered_on(g, s, platform));
  std::vector<LabelMark> out;
  for (std::size_t k = 0; k < lettered.size(); ++k) {
    const episode::ObjectState& o = s.objects[lettered[k]];
    const geom::Point2 c = episode::footprint_centre(o);
    out.push_back({episode::anchor_letter(k), Eigen::Vector3d(c.x(), c.y(), o.top)});
  }
  return out;
}

std::vector<LabelMark> platform_labels(const graph::SceneGraph& g, const episode::WorldState& s) {
  std::vector<LabelMark> out;
  for (std::size_t k = 0; k < g.navigable.size(); ++k) {
    const graph::PlatformId p = g.navigable[k];
    const geom::Region region_W =
        geom::transform(g.platforms[p].polygon_P, episode::platform_frame(g, s, p));
    const geom::Point2 c = inner_point(region_W);
    out.push_back({graph::navigation_key(static_cast<int>(k) + 1),
                   Eigen::Vector3d(c.x(), c.y(), episode::platform_height(g, s, p))});
  }
  return out;
}

}  // namespace mtg::render
