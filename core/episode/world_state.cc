#include "core/episode/world_state.h"

#include <algorithm>

#include "core/graph/free_space.h"
#include "core/util/error.h"

namespace mtg::episode {
namespace {

// Moves an object and everything resting on it (recursively) by t.
void translate_subtree(const graph::SceneGraph& g, WorldState& s, int object, const Eigen::Vector3d& t) {
  ObjectState& o = s.objects[static_cast<std::size_t>(object)];
  o.position += t;
  o.bottom += t.z();
  o.top += t.z();
  for (auto& p : o.footprint) p += t.head<2>();
  for (const int p : g.objects[static_cast<std::size_t>(object)].platforms) {
    s.platform_offset[static_cast<std::size_t>(p)] += t;
    for (const int child : s.children[static_cast<std::size_t>(p)]) translate_subtree(g, s, child, t);
  }
}

}  // namespace

WorldState initial_state(const graph::SceneGraph& g) {
  WorldState s;
  s.objects.resize(g.objects.size());
  for (std::size_t i = 0; i < g.objects.size(); ++i) {
    const graph::GraphObject& o = g.objects[i];
    ObjectState& st = s.objects[i];
    st.parent = o.parent;
    st.position = o.X_WO.translation();
    st.footprint = o.footprint;
    st.bottom = o.bottom;
    st.top = o.top;
  }
  s.children.resize(g.platforms.size());
  for (std::size_t p = 0; p < g.platforms.size(); ++p) s.children[p] = g.platforms[p].items;
  s.platform_offset.assign(g.platforms.size(), Eigen::Vector3d::Zero());
  return s;
}

std::vector<int> pickable_on(const graph::SceneGraph& g, const WorldState& s, int platform) {
  return g.pickable_on(platform, [&s](int p) -> const std::vector<int>& { return objects_on(s, p); });
}

geom::Point2 footprint_centre(const ObjectState& o) { return geom::centroid(geom::Region{{o.footprint}}); }

const std::vector<int>& objects_on(const WorldState& s, int platform) {
  return s.children.at(static_cast<std::size_t>(platform));
}

std::vector<int> everything_on(const graph::SceneGraph& g, const WorldState& s, int platform) {
  std::vector<int> out;
  std::vector<int> stack(s.children.at(static_cast<std::size_t>(platform)).rbegin(),
                         s.children.at(static_cast<std::size_t>(platform)).rend());
  while (!stack.empty()) {
    const int o = stack.back();
    stack.pop_back();
    out.push_back(o);
    const auto& owned = g.objects[static_cast<std::size_t>(o)].platforms;
    for (auto p = owned.rbegin(); p != owned.rend(); ++p) {
      const auto& on = s.children[static_cast<std::size_t>(*p)];
      stack.insert(stack.end(), on.rbegin(), on.rend());
    }
  }
  return out;
}

Eigen::Isometry2d platform_frame(const graph::SceneGraph& g, const WorldState& s, int platform) {
  const Eigen::Vector3d& t = s.platform_offset[static_cast<std::size_t>(platform)];
  return Eigen::Translation2d(t.head<2>()) * g.platforms[static_cast<std::size_t>(platform)].X_WP;
}

double platform_height(const graph::SceneGraph& g, const WorldState& s, int platform) {
  return g.platforms[static_cast<std::size_t>(platform)].height +
         s.platform_offset[static_cast<std::size_t>(platform)].z();
}

std::vector<graph::Obstacle> obstacles_on(const graph::SceneGraph& g, const WorldState& s, int platform) {
  std::vector<graph::Obstacle> out;
  const Eigen::Isometry2d X_PW = platform_frame(g, s, platform).inverse();
  for (const int o : objects_on(s, platform)) {
    graph::Obstacle ob;
    ob.object = o;
    ob.hull_P = geom::transform(s.objects[static_cast<std::size_t>(o)].footprint, X_PW);
    ob.box_P = geom::bounds(ob.hull_P);
    out.push_back(std::move(ob));
  }
  return out;
}

void pick(const graph::SceneGraph& g, WorldState& s, int object) {
  ObjectState& o = s.objects.at(static_cast<std::size_t>(object));
  MTG_DEMAND(s.held < 0, "pick while holding " + g.objects[static_cast<size_t>(s.held)].name);
  if (o.parent >= 0) {
    auto& siblings = s.children[static_cast<std::size_t>(o.parent)];
    siblings.erase(std::remove(siblings.begin(), siblings.end(), object), siblings.end());
  }
  o.parent = -1;
  s.held = object;
}

void place_held(const graph::SceneGraph& g, WorldState& s, int platform, const Eigen::Vector2d& xy) {
  MTG_DEMAND(s.held >= 0, "place with an empty hand");
  const int object = s.held;
  const ObjectState& o = s.objects[static_cast<std::size_t>(object)];
  const Eigen::Vector3d t(xy.x() - o.position.x(), xy.y() - o.position.y(),
                          platform_height(g, s, platform) - o.bottom);
  translate_subtree(g, s, object, t);
  ObjectState& placed = s.objects[static_cast<std::size_t>(object)];
  placed.parent = platform;
  placed.placed_side = s.side;
  s.children[static_cast<std::size_t>(platform)].push_back(object);  // appended: numbers shift
  s.held = -1;
}

double stack_height(const graph::SceneGraph& g, const WorldState& s, int object) {
  const ObjectState& o = s.objects.at(static_cast<std::size_t>(object));
  double top = o.top;
  for (const int p : g.objects[static_cast<std::size_t>(object)].platforms) {
    for (const int above : everything_on(g, s, p)) top = std::max(top, s.objects[static_cast<std::size_t>(above)].top);
  }
  return top - o.bottom;
}

int furniture_platform_of(const graph::SceneGraph& g, const WorldState& s, int object) {
  int p = s.objects.at(static_cast<std::size_t>(object)).parent;
  while (p >= 0) {
    const graph::Platform& plat = g.platforms[static_cast<std::size_t>(p)];
    if (plat.destination) return p;
    p = s.objects[static_cast<std::size_t>(plat.owner)].parent;
  }
  return -1;
}

}  // namespace mtg::episode
