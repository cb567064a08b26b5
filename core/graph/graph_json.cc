#include "core/graph/graph_json.h"

#include <cmath>
#include <map>

#include "core/graph/free_space.h"

namespace mtg::graph {
namespace {

// Rounds to 1/per_unit; dividing (not multiplying by a step) yields the double nearest the
// decimal value, so the JSON prints e.g. 0.8441 rather than 0.8441000000000001.
double round_to(double v, double per_unit) {
  const double r = std::round(v * per_unit) / per_unit;
  return r == 0.0 ? 0.0 : r;  // no "-0"
}
double len(double v) { return round_to(v, 1e4); }
double sq(double v) { return round_to(v, 1e5); }

nlohmann::json point(const Eigen::Vector2d& p) { return {len(p.x()), len(p.y())}; }

nlohmann::json ring(const geom::Ring& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : r) out.push_back(point(p));
  return out;
}

nlohmann::json region(const geom::Region& r) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& rg : r.rings) out.push_back(ring(rg));
  return out;
}

nlohmann::json box(const Eigen::AlignedBox2d& b) { return {point(b.min()), point(b.max())}; }

std::string parent_name(const SceneGraph& g, const GraphObject& o) {
  if (o.parent.valid()) return g.platforms[o.parent].name;
  return "ground";
}

}  // namespace

nlohmann::json graph_summary(const SceneGraph& g) {
  std::map<std::string, int> kinds;
  for (const auto& o : g.objects) kinds[to_string(o.kind)] += 1;
  int destinations = 0, pickable = 0;
  for (const auto& p : g.platforms) destinations += p.destination ? 1 : 0;
  for (const PlatformId p : g.navigable) pickable += static_cast<int>(g.pickable_on(p).size());
  return {{"objects", g.objects.size()},
          {"by_kind", kinds},
          {"platforms", g.platforms.size()},
          {"destinations", destinations},
          {"navigable", g.navigable.size()},
          {"pickable_on_navigable", pickable}};
}

nlohmann::json graph_to_json(const SceneGraph& g, const GraphOptions& options) {
  nlohmann::json j;
  j["format"] = kGraphFormat;
  j["scene"] = g.scene;
  j["options"] = options.to_json();
  j["summary"] = graph_summary(g);

  nlohmann::json platforms = nlohmann::json::array();
  for (const Platform& p : g.platforms) {
    nlohmann::json jp;
    jp["name"] = p.name;
    jp["owner"] = g.objects[p.owner].name;
    jp["index"] = p.index;
    jp["height"] = len(p.height);
    jp["clearance"] = std::isfinite(p.clearance) ? nlohmann::json(len(p.clearance)) : nlohmann::json();
    jp["interior"] = p.interior;
    jp["source"] = p.source;
    jp["destination"] = p.destination;
    jp["navigable"] = p.navigable;
    jp["label"] = p.label > 0 ? nlohmann::json(navigation_key(p.label)) : nlohmann::json();
    const Eigen::Vector2d t = p.X_WP.translation();
    jp["frame"] = {{"x", len(t.x())}, {"y", len(t.y())},
                   {"yaw", round_to(Eigen::Rotation2Dd(p.X_WP.rotation()).angle(), 1e5)}};
    jp["area"] = sq(p.area());
    jp["box"] = box(p.box_P);
    jp["polygon"] = region(p.polygon_P);
    jp["polygon_world"] = region(p.polygon_W());
    std::vector<std::string> items;
    for (const ObjectId o : p.items) items.push_back(g.objects[o].name);
    jp["items"] = items;
    if (p.destination) {
      nlohmann::json sides;
      for (const Side side : kSides) {
        const SideInfo& s = p.sides[static_cast<std::size_t>(side)];
        nlohmann::json js = {{"standing_area", sq(s.standing_area)}, {"visible", s.visible},
                             {"objects_seen", s.objects_seen}, {"sight_lines", s.sight_lines}};
        if (s.standing_area > 0.0) js["standing_point"] = point(s.standing_point);
        sides[to_string(side)] = js;
      }
      jp["sides"] = sides;
      jp["default_side"] = p.default_side >= 0 ? nlohmann::json(to_string(static_cast<Side>(p.default_side)))
                                               : nlohmann::json();
      // Free space in the initial state, in platform-frame directions.
      const std::vector<ObjectId>& on = p.items;
      std::vector<geom::Ring> footprints;
      for (const ObjectId o : on) footprints.push_back(g.objects[o].footprint);
      nlohmann::json regions = nlohmann::json::array();
      if (on.empty()) {
        for (const FreeRegion& r : grid_cells(p)) {
          regions.push_back({{"cell", direction_name(r.dir)}, {"area", sq(geom::area(r.region_P))}});
        }
      } else {
        for (const FreeRegion& r : object_regions(p, make_obstacles(p, on, footprints),
                                                  options.min_region_size)) {
          if (!r.numbered) continue;
          regions.push_back({{"object", g.objects[r.object].name},
                             {"dir", direction_name(r.dir)},
                             {"rect", box(r.rect_P)},
                             {"area", sq(geom::area(r.region_P))}});
        }
      }
      jp["free_space"] = regions;
    }
    platforms.push_back(std::move(jp));
  }
  j["platforms"] = platforms;

  nlohmann::json objects = nlohmann::json::array();
  for (const GraphObject& o : g.objects) {
    nlohmann::json jo;
    jo["name"] = o.name;
    jo["kind"] = to_string(o.kind);
    jo["template"] = o.template_name;
    jo["category"] = o.category;
    if (!o.noun.empty()) jo["noun"] = o.noun;
    jo["movable"] = o.movable;
    const bool in_tree = o.kind == ObjectKind::kFurniture || o.kind == ObjectKind::kItem ||
                         o.kind == ObjectKind::kFixed;
    jo["parent"] = in_tree ? nlohmann::json(parent_name(g, o)) : nlohmann::json();
    jo["bottom"] = len(o.bottom);
    jo["top"] = len(o.top);
    jo["settle_dz"] = len(o.settle_dz);
    jo["heading"] = round_to(o.heading, 1e5);
    jo["position"] = {len(o.X_WO.translation().x()), len(o.X_WO.translation().y()),
                      len(o.X_WO.translation().z())};
    jo["footprint"] = ring(o.footprint);
    std::vector<std::string> own;
    for (const PlatformId p : o.platforms) own.push_back(g.platforms[p].name);
    jo["platforms"] = own;
    if (!o.note.empty()) jo["note"] = o.note;
    objects.push_back(std::move(jo));
  }
  j["objects"] = objects;
  j["navigable"] = [&] {
    std::vector<std::string> names;
    for (const PlatformId p : g.navigable) names.push_back(g.platforms[p].name);
    return names;
  }();
  j["warnings"] = g.warnings;
  return j;
}

}  // namespace mtg::graph
