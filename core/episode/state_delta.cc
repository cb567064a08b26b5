#include "core/episode/state_delta.h"

#include <algorithm>
#include <vector>

#include "core/util/error.h"

namespace mtg::episode {
namespace {

graph::ObjectId object_named(const graph::SceneGraph& g, const std::string& name, const std::string& field) {
  const graph::ObjectId i = g.find_object(name);
  if (!i.valid()) throw Error("state: '" + field + "' names no object of scene " + g.scene + ": '" + name + "'");
  return i;
}

// "" is no platform.
graph::PlatformId platform_named(const graph::SceneGraph& g, const std::string& name, const std::string& field) {
  if (name.empty()) return {};
  const graph::PlatformId i = g.find_platform(name);
  if (!i.valid()) throw Error("state: '" + field + "' names no platform of scene " + g.scene + ": '" + name + "'");
  return i;
}

// A platform a list entry is about: "" is an error there.
graph::PlatformId platform_listed(const graph::SceneGraph& g, const std::string& name, const std::string& field) {
  if (name.empty()) throw Error("state: '" + field + "' is empty");
  return platform_named(g, name, field);
}

std::string platform_name(const graph::SceneGraph& g, graph::PlatformId p) {
  return p.valid() ? g.platforms[p].name : std::string();
}

bool same(const ObjectState& a, const ObjectState& b) {
  return a.parent == b.parent && a.position == b.position && a.footprint == b.footprint && a.bottom == b.bottom &&
         a.top == b.top && a.placed_side == b.placed_side;
}

}  // namespace

StateDelta state_delta(const graph::SceneGraph& g, const WorldState& s) {
  const WorldState initial = initial_state(g, s.numbering);
  StateDelta d;
  d.numbering = s.numbering;
  d.phase = s.phase;
  d.at = platform_name(g, s.at_platform);
  d.side = s.side;
  d.held = !s.held.valid() ? std::string() : g.objects[s.held].name;
  d.steps = s.steps;
  for (const graph::ObjectId i : s.objects.ids()) {
    const ObjectState& o = s.objects[i];
    if (same(o, initial.objects[i])) continue;
    d.moved.push_back({g.objects[i].name, platform_name(g, o.parent), o.position, o.footprint, o.bottom, o.top,
                       o.placed_side});
  }
  for (const graph::PlatformId p : s.children.ids()) {
    const std::string& name = g.platforms[p].name;
    if (s.children[p] != initial.children[p]) {
      PlatformOrder order{name, {}};
      for (const graph::ObjectId o : s.children[p]) order.objects.push_back(g.objects[o].name);
      d.reordered.push_back(std::move(order));
    }
    if (!s.platform_offset[p].isZero(0.0)) d.offsets.push_back({name, s.platform_offset[p]});
    if (p.index() < s.numbered.size() && !s.numbered[p].empty()) {
      PlatformOrder order{name, {}};
      for (const graph::ObjectId o : s.numbered[p]) order.objects.push_back(o.valid() ? g.objects[o].name : std::string());
      d.numbered.push_back(std::move(order));
    }
  }
  return d;
}

WorldState apply_delta(const graph::SceneGraph& g, const StateDelta& delta) {
  if (delta.numbering != Numbering::kStable && delta.numbering != Numbering::kPerState) {
    throw Error("state: 'numbering' must be 0 (stable) or 1 (per_state), got " +
                std::to_string(static_cast<int>(delta.numbering)));
  }
  if (delta.numbering == Numbering::kPerState && !delta.numbered.empty()) {
    throw Error("state: 'numbered' lists numbers kept, which per_state numbering has none of");
  }
  WorldState s = initial_state(g, delta.numbering);
  const int phase = static_cast<int>(delta.phase);
  if (phase < static_cast<int>(Phase::kStart) || phase > static_cast<int>(Phase::kDone)) {
    throw Error("state: 'phase' must be 0..3 (start, at_platform, placing, done), got " + std::to_string(phase));
  }
  s.phase = delta.phase;
  s.at_platform = platform_named(g, delta.at, "at");
  if (delta.side < -1 || delta.side > 3) throw Error("state: 'side' must be -1..3, got " + std::to_string(delta.side));
  s.side = delta.side;
  s.held = delta.held.empty() ? graph::ObjectId() : object_named(g, delta.held, "held");
  s.steps = delta.steps;
  // Each object and platform at most once: a list that names one twice would silently keep the last.
  IdVector<graph::ObjectId, bool> moved_seen(s.objects.size(), false);
  IdVector<graph::PlatformId, bool> reordered_seen(s.children.size(), false), offset_seen(s.children.size(), false);
  const auto once = [](auto& seen, auto i, const std::string& field, const std::string& name) {
    if (seen[i]) throw Error("state: '" + field + "' names '" + name + "' twice");
    seen[i] = true;
  };
  for (const MovedObject& m : delta.moved) {
    const graph::ObjectId i = object_named(g, m.object, "moved.object");
    once(moved_seen, i, "moved.object", m.object);
    if (m.placed_side < -1 || m.placed_side > 3) {
      throw Error("state: 'moved.placed_side' of '" + m.object + "' must be -1..3, got " + std::to_string(m.placed_side));
    }
    ObjectState& o = s.objects[i];
    o.parent = platform_named(g, m.parent, "moved.parent");
    o.position = m.position;
    o.footprint = m.footprint;
    o.bottom = m.bottom;
    o.top = m.top;
    o.placed_side = m.placed_side;
  }
  for (const PlatformOrder& order : delta.reordered) {
    const graph::PlatformId p = platform_listed(g, order.platform, "reordered.platform");
    once(reordered_seen, p, "reordered.platform", order.platform);
    std::vector<graph::ObjectId>& children = s.children[p];
    children.clear();
    for (const std::string& o : order.objects) children.push_back(object_named(g, o, "reordered." + order.platform));
  }
  for (const PlatformOffset& offset : delta.offsets) {
    const graph::PlatformId p = platform_listed(g, offset.platform, "offsets.platform");
    once(offset_seen, p, "offsets.platform", offset.platform);
    s.platform_offset[p] = offset.offset;
  }
  IdVector<graph::PlatformId, bool> numbered_seen(s.children.size(), false);
  for (const PlatformOrder& order : delta.numbered) {
    const graph::PlatformId p = platform_listed(g, order.platform, "numbered.platform");
    once(numbered_seen, p, "numbered.platform", order.platform);
    if (order.objects.empty()) throw Error("state: 'numbered' of '" + order.platform + "' lists no number");
    std::vector<graph::ObjectId>& numbers = s.numbered[p];
    for (const std::string& o : order.objects) {
      const graph::ObjectId i = o.empty() ? graph::ObjectId() : object_named(g, o, "numbered." + order.platform);
      if (i.valid() && std::find(numbers.begin(), numbers.end(), i) != numbers.end()) {
        throw Error("state: 'numbered' of '" + order.platform + "' numbers '" + o + "' twice");
      }
      numbers.push_back(i);
    }
  }
  return s;
}

}  // namespace mtg::episode
