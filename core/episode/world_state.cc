#include "core/episode/world_state.h"

#include <algorithm>

#include "core/graph/free_space.h"
#include "core/util/error.h"

namespace mtg::episode {
namespace {

// Moves an object and everything resting on it (recursively) by t.
void translate_subtree(const graph::SceneGraph& g, WorldState& s, graph::ObjectId object, const Eigen::Vector3d& t) {
  ObjectState& o = s.objects[object];
  o.position += t;
  o.bottom += t.z();
  o.top += t.z();
  for (auto& p : o.footprint) p += t.head<2>();
  for (const graph::PlatformId p : g.objects[object].platforms) {
    s.platform_offset[p] += t;
    for (const graph::ObjectId child : s.children[p]) translate_subtree(g, s, child, t);
  }
}

// `platform`, or the furniture platform the item owning it stands on (furniture_platform_of).
graph::PlatformId furniture_platform(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  graph::PlatformId p = platform;
  while (p.valid()) {
    const graph::Platform& plat = g.platforms[p];
    if (plat.destination) return p;
    p = s.objects[plat.owner].parent;
  }
  return {};
}

// `object`, then everything resting on it (pickable_on's order).
std::vector<graph::ObjectId> subtree_of(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  std::vector<graph::ObjectId> out = {object};
  const std::vector<graph::ObjectId> above = resting_on(g, s, object);
  out.insert(out.end(), above.begin(), above.end());
  return out;
}

// The numbers `platform` keeps (stable numbering), made from pickable_on's order the first time
// something leaves or arrives there.
std::vector<graph::ObjectId>& kept_numbers(const graph::SceneGraph& g, WorldState& s, graph::PlatformId platform) {
  if (s.numbered.size() < g.platforms.size()) s.numbered.resize(g.platforms.size());
  std::vector<graph::ObjectId>& numbers = s.numbered[platform];
  if (numbers.empty()) numbers = pickable_on(g, s, platform);
  return numbers;
}

}  // namespace

const char* to_string(Numbering numbering) { return numbering == Numbering::kStable ? "stable" : "per_state"; }

Numbering numbering_from_string(std::string_view name, std::string_view what) {
  for (const Numbering n : {Numbering::kStable, Numbering::kPerState}) {
    if (name == to_string(n)) return n;
  }
  throw Error(std::string(what) + " is stable or per_state, not '" + std::string(name) + "'");
}

WorldState initial_state(const graph::SceneGraph& g, Numbering numbering) {
  WorldState s;
  s.numbering = numbering;
  s.objects.resize(g.objects.size());
  for (const graph::ObjectId i : g.objects.ids()) {
    const graph::GraphObject& o = g.objects[i];
    ObjectState& st = s.objects[i];
    st.parent = o.parent;
    st.position = o.X_WO.translation();
    st.footprint = o.footprint;
    st.bottom = o.bottom;
    st.top = o.top;
  }
  s.children.resize(g.platforms.size());
  for (const graph::PlatformId p : g.platforms.ids()) s.children[p] = g.platforms[p].items;
  s.platform_offset.resize(g.platforms.size(), Eigen::Vector3d::Zero());
  s.numbered.resize(g.platforms.size());
  return s;
}

std::vector<graph::ObjectId> pickable_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  return g.pickable_on(platform,
                       [&s](graph::PlatformId p) -> const std::vector<graph::ObjectId>& { return objects_on(s, p); });
}

std::vector<graph::ObjectId> numbered_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  if (platform.index() < s.numbered.size() && !s.numbered[platform].empty()) return s.numbered[platform];
  return pickable_on(g, s, platform);
}

int number_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform, graph::ObjectId object) {
  if (!object.valid()) return 0;
  const std::vector<graph::ObjectId> items = numbered_on(g, s, platform);
  const auto it = std::find(items.begin(), items.end(), object);
  return it == items.end() ? 0 : static_cast<int>(it - items.begin()) + 1;
}

int number_of(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  const graph::PlatformId platform = furniture_platform_of(g, s, object);
  return platform.valid() ? number_on(g, s, platform, object) : 0;
}

std::string object_key(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  const int n = number_of(g, s, object);
  return n > 0 ? "o" + std::to_string(n) : std::string();
}

geom::Point2 footprint_centre(const ObjectState& o) { return geom::centroid(geom::Region{{o.footprint}}); }

const std::vector<graph::ObjectId>& objects_on(const WorldState& s, graph::PlatformId platform) {
  return s.children.at(platform);
}

std::vector<graph::ObjectId> everything_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  std::vector<graph::ObjectId> out;
  const std::vector<graph::ObjectId>& direct = s.children.at(platform);
  std::vector<graph::ObjectId> stack(direct.rbegin(), direct.rend());
  while (!stack.empty()) {
    const graph::ObjectId o = stack.back();
    stack.pop_back();
    out.push_back(o);
    const auto& owned = g.objects[o].platforms;
    for (auto p = owned.rbegin(); p != owned.rend(); ++p) {
      const auto& on = s.children[*p];
      stack.insert(stack.end(), on.rbegin(), on.rend());
    }
  }
  return out;
}

Eigen::Isometry2d platform_frame(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  const Eigen::Vector3d& t = s.platform_offset[platform];
  return Eigen::Translation2d(t.head<2>()) * g.platforms[platform].X_WP;
}

double platform_height(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  return g.platforms[platform].height + s.platform_offset[platform].z();
}

std::vector<graph::Obstacle> obstacles_on(const graph::SceneGraph& g, const WorldState& s, graph::PlatformId platform) {
  std::vector<graph::Obstacle> out;
  const Eigen::Isometry2d X_PW = platform_frame(g, s, platform).inverse();
  for (const graph::ObjectId o : objects_on(s, platform)) {
    graph::Obstacle ob;
    ob.object = o;
    ob.hull_P = geom::transform(s.objects[o].footprint, X_PW);
    ob.box_P = geom::bounds(ob.hull_P);
    out.push_back(std::move(ob));
  }
  return out;
}

void pick(const graph::SceneGraph& g, WorldState& s, graph::ObjectId object) {
  ObjectState& o = s.objects.at(object);
  MTG_DEMAND(!s.held.valid(), "pick while holding " + g.objects[s.held].name);
  if (s.numbering == Numbering::kStable) {
    // The item and what rides on it leave the platform's numbering; their numbers stay theirs
    // (retired), so no other item takes them.
    const graph::PlatformId from = furniture_platform_of(g, s, object);
    if (from.valid()) {
      std::vector<graph::ObjectId>& numbers = kept_numbers(g, s, from);
      const std::vector<graph::ObjectId> leaving = subtree_of(g, s, object);
      for (graph::ObjectId& n : numbers) {
        if (std::find(leaving.begin(), leaving.end(), n) != leaving.end()) n = {};
      }
    }
  }
  if (o.parent.valid()) {
    auto& siblings = s.children[o.parent];
    siblings.erase(std::remove(siblings.begin(), siblings.end(), object), siblings.end());
  }
  o.parent = {};
  s.held = object;
}

void place_held(const graph::SceneGraph& g, WorldState& s, graph::PlatformId platform, const Eigen::Vector2d& xy) {
  MTG_DEMAND(s.held.valid(), "place with an empty hand");
  const graph::ObjectId object = s.held;
  const ObjectState& o = s.objects[object];
  const Eigen::Vector3d t(xy.x() - o.position.x(), xy.y() - o.position.y(),
                          platform_height(g, s, platform) - o.bottom);
  translate_subtree(g, s, object, t);
  // The furniture platform's numbering as it was before this arrival (stable numbering).
  std::vector<graph::ObjectId>* numbers = nullptr;
  if (s.numbering == Numbering::kStable) {
    const graph::PlatformId owner_platform = furniture_platform(g, s, platform);
    if (owner_platform.valid()) numbers = &kept_numbers(g, s, owner_platform);
  }
  ObjectState& placed = s.objects[object];
  placed.parent = platform;
  placed.placed_side = s.side;
  s.children[platform].push_back(object);  // appended: per-state numbers shift
  s.held = {};
  if (numbers != nullptr) {
    // The item, then what rides on it, in pickable_on's order, after the highest number so far.
    for (const graph::ObjectId arrived : subtree_of(g, s, object)) {
      if (g.objects[arrived].pickable()) numbers->push_back(arrived);
    }
  }
}

std::vector<graph::ObjectId> resting_on(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  std::vector<graph::ObjectId> out;
  for (const graph::PlatformId p : g.objects[object].platforms) {
    const std::vector<graph::ObjectId> on = everything_on(g, s, p);
    out.insert(out.end(), on.begin(), on.end());
  }
  return out;
}

std::vector<graph::ObjectId> in_hand(const graph::SceneGraph& g, const WorldState& s) {
  return s.held.valid() ? subtree_of(g, s, s.held) : std::vector<graph::ObjectId>{};
}

bool carried(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  if (!s.held.valid()) return false;
  for (graph::ObjectId o = object;;) {
    if (o == s.held) return true;
    const graph::PlatformId p = s.objects[o].parent;
    if (!p.valid()) return false;
    o = g.platforms[p].owner;
    if (!o.valid()) return false;
  }
}

double stack_height(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  const ObjectState& o = s.objects.at(object);
  double top = o.top;
  for (const graph::PlatformId p : g.objects[object].platforms) {
    for (const graph::ObjectId above : everything_on(g, s, p)) top = std::max(top, s.objects[above].top);
  }
  return top - o.bottom;
}

graph::PlatformId furniture_platform_of(const graph::SceneGraph& g, const WorldState& s, graph::ObjectId object) {
  return furniture_platform(g, s, s.objects.at(object).parent);
}

}  // namespace mtg::episode
