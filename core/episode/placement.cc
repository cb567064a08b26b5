#include "core/episode/placement.h"

#include <algorithm>

namespace mtg::episode {
namespace {

constexpr double kMargin = 0.001;  // keep a millimetre between placed footprints

// The anchor point of direction `dir` on box `b`: edge midpoints for sides, corners for corners.
geom::Point2 aim_on_box(const Eigen::AlignedBox2d& b, int dir) {
  const double cx = b.center().x(), cy = b.center().y();
  switch (dir) {
    case 0: return {cx, b.min().y()};
    case 1: return {b.min().x(), b.min().y()};
    case 2: return {b.min().x(), cy};
    case 3: return {b.min().x(), b.max().y()};
    case 4: return {cx, b.max().y()};
    case 5: return {b.max().x(), b.max().y()};
    case 6: return {b.max().x(), cy};
    default: return {b.max().x(), b.min().y()};
  }
}

// A ring's coordinates, appended to a memo key.
void append_ring(std::string& key, const geom::Ring& ring) {
  append_key(key, ring.size());
  for (const geom::Point2& q : ring) {
    append_key(key, q.x());
    append_key(key, q.y());
  }
}

geom::Region inset_of(const geom::Region& region, PlacementMemo* memo) {
  const auto make = [&] { return geom::offset(region, -kPlacementInset); };
  if (memo == nullptr) return make();
  std::string key;
  for (const geom::Ring& ring : region.rings) append_ring(key, ring);
  return memo->tables->insets.get(key, make);
}

// An empty platform's targets: its nine grid cells (which depend on the platform alone).
std::vector<PlaceTarget> grid_targets(const graph::Platform& p, graph::PlatformId platform, graph::Side side,
                                      PlacementMemo* memo) {
  const auto make_cells = [&] { return graph::grid_cells(p); };
  std::string key;
  if (memo != nullptr) append_key(key, platform.value());
  std::array<graph::FreeRegion, 9> own;
  const auto& cells = memo == nullptr ? (own = make_cells()) : memo->tables->cells.get(key, make_cells);
  std::vector<PlaceTarget> out;
  for (int rel = 0; rel <= graph::kCentre; ++rel) {
    const int dir = graph::platform_direction(rel, side);
    PlaceTarget t;
    t.key = std::to_string(rel + 1);
    t.kind = PlaceTarget::Kind::kGridCell;
    t.relative_dir = rel;
    t.platform_dir = dir;
    t.region_P = cells[static_cast<std::size_t>(dir)].region_P;
    t.aim_P = cells[static_cast<std::size_t>(dir)].rect_P.center();
    out.push_back(std::move(t));
  }
  return out;
}

// An occupied platform's targets: the numbered free regions of the objects on it.
std::vector<PlaceTarget> object_targets(const graph::Platform& p, graph::PlatformId platform,
                                        const std::vector<graph::Obstacle>& obstacles, graph::Side side,
                                        double min_region_size, PlacementMemo* memo) {
  graph::RectClip clip;
  if (memo != nullptr) {
    clip = [&](const Eigen::AlignedBox2d& rect) {
      std::string key;
      append_key(key, platform.value());
      for (const double v : {rect.min().x(), rect.min().y(), rect.max().x(), rect.max().y()}) append_key(key, v);
      return memo->tables->clips.get(key, [&] { return graph::clip_to_polygon(p, rect); });
    };
  }
  const auto regions = graph::object_regions(p, obstacles, min_region_size, clip);
  std::vector<PlaceTarget> out;
  int next = 1;
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    for (int rel = 0; rel < graph::kNumDirections; ++rel) {
      const int dir = graph::platform_direction(rel, side);
      const graph::FreeRegion& r = regions[8 * k + static_cast<std::size_t>(dir)];
      if (!r.numbered) continue;
      PlaceTarget t;
      t.key = std::to_string(next++);
      if (t.key == kAnywhereKey) t.key = std::to_string(next++);  // that key is "anywhere", on every platform
      t.kind = PlaceTarget::Kind::kObjectRegion;
      t.relative_dir = rel;
      t.platform_dir = dir;
      t.anchor = obstacles[k].object;
      t.region_P = r.region_P;
      t.aim_P = aim_on_box(obstacles[k].box_P, dir);
      out.push_back(std::move(t));
    }
  }
  return out;
}

}  // namespace

std::string display_name(const graph::GraphObject& o) {
  std::string name = o.short_name.empty() ? o.name : o.short_name;
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

std::string listed_name(const graph::GraphObject& o) {
  const std::string model = display_name(o);
  return o.noun.empty() || o.noun == model ? model : o.noun + " (" + model + ")";
}

std::vector<PlaceTarget> place_targets(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform,
                                       graph::Side side, double min_region_size, PlacementMemo* memo) {
  const graph::Platform& p = g.platforms.at(platform);
  std::vector<PlaceTarget> out;
  if (objects_on(s, platform).empty()) {
    out = grid_targets(p, platform, side, memo);
  } else {
    const std::vector<graph::Obstacle> obstacles = obstacles_on(g, s, platform);
    const auto make = [&] { return object_targets(p, platform, obstacles, side, min_region_size, memo); };
    if (memo == nullptr || !memo->whole_results) {
      out = make();
    } else {
      // What the targets depend on: the platform, the side, the size rule and every obstacle.
      std::string key;
      append_key(key, platform.value());
      append_key(key, side);
      append_key(key, min_region_size);
      for (const graph::Obstacle& o : obstacles) {
        append_key(key, o.object.value());
        append_ring(key, o.hull_P);
      }
      out = memo->last_targets.get(key, make);
    }
  }
  out.push_back(anywhere_target(p));
  return out;
}

PlaceTarget anywhere_target(const graph::Platform& platform) {
  PlaceTarget any;
  any.key = kAnywhereKey;
  any.region_P = platform.polygon_P;
  any.aim_P = geom::centroid(platform.polygon_P);
  return any;
}

std::vector<graph::ObjectId> lettered_anchors(const std::vector<PlaceTarget>& targets,
                                              const std::vector<graph::ObjectId>& numbering) {
  std::vector<graph::ObjectId> out;
  for (const PlaceTarget& t : targets) {
    if (t.kind != PlaceTarget::Kind::kObjectRegion || !t.anchor.valid()) continue;
    if (std::find(numbering.begin(), numbering.end(), t.anchor) != numbering.end()) continue;
    if (std::find(out.begin(), out.end(), t.anchor) == out.end()) out.push_back(t.anchor);
  }
  return out;
}

std::string anchor_letter(std::size_t index) {
  std::string out(1, static_cast<char>('A' + index % 26));
  if (index >= 26) out += std::to_string(index / 26 + 1);
  return out;
}

void with_insets(std::vector<PlaceTarget>& targets, PlacementMemo* memo) {
  for (PlaceTarget& t : targets) t.region_inset_P = inset_of(t.region_P, memo);
}

geom::Ring held_footprint_P(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  const ObjectState& o = s.objects.at(s.held);
  const geom::Point2 c = footprint_centre(o);
  const Eigen::Rotation2Dd R_PW(platform_frame(g, s, platform).rotation().transpose());
  geom::Ring out;
  for (const auto& q : o.footprint) out.push_back(R_PW * (q - c));
  return out;
}

FeasibleCentres held_feasible_centres(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform,
                                      PlacementMemo* memo) {
  const graph::Platform& p = g.platforms.at(platform);
  const std::vector<graph::Obstacle> obstacles = obstacles_on(g, s, platform);
  const geom::Ring item = held_footprint_P(g, s, platform);
  std::string key;  // the platform and the item's footprint, then the obstacles'
  if (memo != nullptr) {
    append_key(key, platform.value());
    append_ring(key, item);
  }
  const auto make = [&] {
    const auto interior = [&] { return graph::placeable_interior(p, item); };
    const geom::Region free =
        graph::clear_of(memo == nullptr ? interior() : memo->tables->interiors.get(key, interior), obstacles, item);
    FeasibleCentres out;
    if (free.empty()) return out;
    out.all = geom::offset(free, -kMargin);
    if (!out.all.empty()) out.inset = geom::offset(out.all, -kPlacementInset);
    return out;
  };
  if (memo == nullptr || !memo->whole_results) return make();
  std::string full = key;
  for (const graph::Obstacle& o : obstacles) append_ring(full, o.hull_P);
  return memo->feasible.get(full, make);
}

std::optional<Eigen::Vector2d> resolve_target(const graph::SceneGraph& g, const WorldState& s,
                                              graph::PlatformId platform, const PlaceTarget& target,
                                              const FeasibleCentres& feasible_centres, PlacementMemo* memo) {
  // Erosion distributes over intersection: the inset candidates are the inset pieces' overlap.
  const auto usable = [](const geom::Region& r) { return !r.empty() && geom::area(r) >= 1e-10; };
  const geom::Region computed = target.region_inset_P ? geom::Region{} : inset_of(target.region_P, memo);
  geom::Region candidates =
      geom::intersect(feasible_centres.inset, target.region_inset_P ? *target.region_inset_P : computed);
  if (!usable(candidates)) {
    candidates = geom::intersect(feasible_centres.all, target.region_P);
    if (!usable(candidates)) return std::nullopt;
  }
  const geom::Point2 centre_P = geom::closest_point(candidates, target.aim_P);
  const Eigen::Vector2d centre_W = platform_frame(g, s, platform) * centre_P;
  // Reference point = centre minus the centre's offset from the object's origin.
  const ObjectState& o = s.objects.at(s.held);
  const geom::Point2 c = footprint_centre(o);
  return centre_W - (c - o.position.head<2>());
}

}  // namespace mtg::episode
