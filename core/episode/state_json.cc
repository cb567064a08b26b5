#include "core/episode/state_json.h"

#include "core/util/error.h"

namespace mtg::episode {
namespace {

using nlohmann::json;

json point(const Eigen::Vector3d& p) { return json::array({p.x(), p.y(), p.z()}); }

Eigen::Vector3d point3(const json& j, const std::string& field) {
  if (!j.is_array() || j.size() != 3) throw Error("state: '" + field + "' must be [x, y, z]");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

int object_named(const graph::SceneGraph& g, const json& name, const std::string& field) {
  const int i = name.is_string() ? g.find_object(name.get<std::string>()) : -1;
  if (i < 0) throw Error("state: '" + field + "' names no object of scene " + g.scene + ": " + name.dump());
  return i;
}

int platform_named(const graph::SceneGraph& g, const json& name, const std::string& field) {
  if (name.is_null()) return -1;
  const int i = name.is_string() ? g.find_platform(name.get<std::string>()) : -1;
  if (i < 0) throw Error("state: '" + field + "' names no platform of scene " + g.scene + ": " + name.dump());
  return i;
}

json platform_name(const graph::SceneGraph& g, int p) {
  return p < 0 ? json(nullptr) : json(g.platforms[static_cast<std::size_t>(p)].name);
}

bool same(const ObjectState& a, const ObjectState& b) {
  return a.parent == b.parent && a.position == b.position && a.footprint == b.footprint && a.bottom == b.bottom &&
         a.top == b.top && a.placed_side == b.placed_side;
}

constexpr const char* kPhases[] = {"start", "at_platform", "placing", "done"};

}  // namespace

json state_delta_to_json(const graph::SceneGraph& g, const WorldState& s) {
  const WorldState initial = initial_state(g);
  json out = json::object();
  out["phase"] = kPhases[static_cast<int>(s.phase)];
  out["at"] = platform_name(g, s.at_platform);
  out["side"] = s.side;
  out["held"] = s.held < 0 ? json(nullptr) : json(g.objects[static_cast<std::size_t>(s.held)].name);
  out["steps"] = s.steps;
  json moved = json::array();
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const ObjectState& o = s.objects[i];
    if (same(o, initial.objects[i])) continue;
    json footprint = json::array();
    for (const auto& p : o.footprint) footprint.push_back({p.x(), p.y()});
    moved.push_back({{"object", g.objects[i].name},
                     {"parent", platform_name(g, o.parent)},
                     {"position", point(o.position)},
                     {"footprint", std::move(footprint)},
                     {"bottom", o.bottom},
                     {"top", o.top},
                     {"placed_side", o.placed_side}});
  }
  out["moved"] = std::move(moved);
  json children = json::object();
  json offsets = json::object();
  for (std::size_t p = 0; p < s.children.size(); ++p) {
    const std::string& name = g.platforms[p].name;
    if (s.children[p] != initial.children[p]) {
      json list = json::array();
      for (const int o : s.children[p]) list.push_back(g.objects[static_cast<std::size_t>(o)].name);
      children[name] = std::move(list);
    }
    if (!s.platform_offset[p].isZero(0.0)) offsets[name] = point(s.platform_offset[p]);
  }
  out["children"] = std::move(children);
  out["platform_offset"] = std::move(offsets);
  return out;
}

WorldState state_from_delta_json(const graph::SceneGraph& g, const json& delta) {
  WorldState s = initial_state(g);
  if (delta.is_null()) return s;
  if (!delta.is_object()) throw Error("state: expected a JSON object, got " + std::string(delta.type_name()));
  try {
    if (delta.contains("phase")) {
      const std::string phase = delta.at("phase").get<std::string>();
      int k = 0;
      while (k < 4 && phase != kPhases[k]) ++k;
      if (k == 4) throw Error("state: 'phase' is not one of start, at_platform, placing, done: " + phase);
      s.phase = static_cast<Phase>(k);
    }
    s.at_platform = platform_named(g, delta.value("at", json(nullptr)), "at");
    s.side = delta.value("side", -1);
    if (s.side < -1 || s.side > 3) throw Error("state: 'side' must be -1..3, got " + std::to_string(s.side));
    const json held = delta.value("held", json(nullptr));
    s.held = held.is_null() ? -1 : object_named(g, held, "held");
    s.steps = delta.value("steps", 0);
    // value() returns a copy: keep each one alive while iterating over it.
    const json moved = delta.value("moved", json::array());
    const json reordered = delta.value("children", json::object());
    const json offsets = delta.value("platform_offset", json::object());
    for (const json& m : moved) {
      const int i = object_named(g, m.at("object"), "moved.object");
      ObjectState& o = s.objects[static_cast<std::size_t>(i)];
      o.parent = platform_named(g, m.at("parent"), "moved.parent");
      o.position = point3(m.at("position"), "moved.position");
      o.footprint.clear();
      for (const json& p : m.at("footprint")) o.footprint.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
      o.bottom = m.at("bottom").get<double>();
      o.top = m.at("top").get<double>();
      o.placed_side = m.at("placed_side").get<int>();
    }
    for (const auto& [name, list] : reordered.items()) {
      const int p = platform_named(g, json(name), "children");
      std::vector<int>& children = s.children[static_cast<std::size_t>(p)];
      children.clear();
      for (const json& o : list) children.push_back(object_named(g, o, "children." + name));
    }
    for (const auto& [name, t] : offsets.items()) {
      const int p = platform_named(g, json(name), "platform_offset");
      s.platform_offset[static_cast<std::size_t>(p)] = point3(t, "platform_offset." + name);
    }
  } catch (const json::exception& e) {
    throw Error(std::string("state: malformed delta: ") + e.what());
  }
  return s;
}

}  // namespace mtg::episode
