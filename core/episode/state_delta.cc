#include "core/episode/state_delta.h"

#include <vector>

#include "core/util/error.h"

namespace mtg::episode {
namespace {

int object_named(const graph::SceneGraph& g, const std::string& name, const std::string& field) {
  const int i = g.find_object(name);
  if (i < 0) throw Error("state: '" + field + "' names no object of scene " + g.scene + ": '" + name + "'");
  return i;
}

// "" is no platform.
int platform_named(const graph::SceneGraph& g, const std::string& name, const std::string& field) {
  if (name.empty()) return -1;
  const int i = g.find_platform(name);
  if (i < 0) throw Error("state: '" + field + "' names no platform of scene " + g.scene + ": '" + name + "'");
  return i;
}

// A platform a list entry is about: "" is an error there.
int platform_listed(const graph::SceneGraph& g, const std::string& name, const std::string& field) {
  if (name.empty()) throw Error("state: '" + field + "' is empty");
  return platform_named(g, name, field);
}

std::string platform_name(const graph::SceneGraph& g, int p) {
  return p < 0 ? std::string() : g.platforms[static_cast<std::size_t>(p)].name;
}

bool same(const ObjectState& a, const ObjectState& b) {
  return a.parent == b.parent && a.position == b.position && a.footprint == b.footprint && a.bottom == b.bottom &&
         a.top == b.top && a.placed_side == b.placed_side;
}

}  // namespace

StateDelta state_delta(const graph::SceneGraph& g, const WorldState& s) {
  const WorldState initial = initial_state(g);
  StateDelta d;
  d.phase = s.phase;
  d.at = platform_name(g, s.at_platform);
  d.side = s.side;
  d.held = s.held < 0 ? std::string() : g.objects[static_cast<std::size_t>(s.held)].name;
  d.steps = s.steps;
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const ObjectState& o = s.objects[i];
    if (same(o, initial.objects[i])) continue;
    d.moved.push_back({g.objects[i].name, platform_name(g, o.parent), o.position, o.footprint, o.bottom, o.top,
                       o.placed_side});
  }
  for (std::size_t p = 0; p < s.children.size(); ++p) {
    const std::string& name = g.platforms[p].name;
    if (s.children[p] != initial.children[p]) {
      PlatformOrder order{name, {}};
      for (const int o : s.children[p]) order.objects.push_back(g.objects[static_cast<std::size_t>(o)].name);
      d.reordered.push_back(std::move(order));
    }
    if (!s.platform_offset[p].isZero(0.0)) d.offsets.push_back({name, s.platform_offset[p]});
  }
  return d;
}

WorldState apply_delta(const graph::SceneGraph& g, const StateDelta& delta) {
  WorldState s = initial_state(g);
  const int phase = static_cast<int>(delta.phase);
  if (phase < static_cast<int>(Phase::kStart) || phase > static_cast<int>(Phase::kDone)) {
    throw Error("state: 'phase' must be 0..3 (start, at_platform, placing, done), got " + std::to_string(phase));
  }
  s.phase = delta.phase;
  s.at_platform = platform_named(g, delta.at, "at");
  if (delta.side < -1 || delta.side > 3) throw Error("state: 'side' must be -1..3, got " + std::to_string(delta.side));
  s.side = delta.side;
  s.held = delta.held.empty() ? -1 : object_named(g, delta.held, "held");
  s.steps = delta.steps;
  // Each object and platform at most once: a list that names one twice would silently keep the last.
  std::vector<bool> moved_seen(s.objects.size(), false), reordered_seen(s.children.size(), false),
      offset_seen(s.children.size(), false);
  const auto once = [](std::vector<bool>& seen, int i, const std::string& field, const std::string& name) {
    if (seen[static_cast<std::size_t>(i)]) throw Error("state: '" + field + "' names '" + name + "' twice");
    seen[static_cast<std::size_t>(i)] = true;
  };
  for (const MovedObject& m : delta.moved) {
    const int i = object_named(g, m.object, "moved.object");
    once(moved_seen, i, "moved.object", m.object);
    if (m.placed_side < -1 || m.placed_side > 3) {
      throw Error("state: 'moved.placed_side' of '" + m.object + "' must be -1..3, got " + std::to_string(m.placed_side));
    }
    ObjectState& o = s.objects[static_cast<std::size_t>(i)];
    o.parent = platform_named(g, m.parent, "moved.parent");
    o.position = m.position;
    o.footprint = m.footprint;
    o.bottom = m.bottom;
    o.top = m.top;
    o.placed_side = m.placed_side;
  }
  for (const PlatformOrder& order : delta.reordered) {
    const int p = platform_listed(g, order.platform, "reordered.platform");
    once(reordered_seen, p, "reordered.platform", order.platform);
    std::vector<int>& children = s.children[static_cast<std::size_t>(p)];
    children.clear();
    for (const std::string& o : order.objects) children.push_back(object_named(g, o, "reordered." + order.platform));
  }
  for (const PlatformOffset& offset : delta.offsets) {
    const int p = platform_listed(g, offset.platform, "offsets.platform");
    once(offset_seen, p, "offsets.platform", offset.platform);
    s.platform_offset[static_cast<std::size_t>(p)] = offset.offset;
  }
  return s;
}

}  // namespace mtg::episode
