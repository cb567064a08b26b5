#include "core/graph/scene_graph.h"

namespace mtg::graph {

const char* to_string(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kFurniture: return "furniture";
    case ObjectKind::kItem: return "item";
    case ObjectKind::kFixed: return "fixed";
    case ObjectKind::kFloorCovering: return "floor_covering";
    case ObjectKind::kUnsupported: return "unsupported";
  }
  return "?";
}

const char* to_string(Side side) {
  switch (side) {
    case Side::kRear: return "rear";
    case Side::kLeft: return "left";
    case Side::kFront: return "front";
    case Side::kRight: return "right";
  }
  return "?";
}

std::string navigation_key(int label) {
  std::string key(1, 'l');
  key += std::to_string(label);
  return key;
}

geom::Region Platform::polygon_W() const { return geom::transform(polygon_P, X_WP); }

int SceneGraph::find_object(const std::string& name) const {
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int SceneGraph::find_platform(const std::string& name) const {
  for (std::size_t i = 0; i < platforms.size(); ++i) {
    if (platforms[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<int> SceneGraph::pickable_on(int platform) const {
  return pickable_on(platform, [this](int p) -> const std::vector<int>& {
    return platforms.at(static_cast<std::size_t>(p)).items;
  });
}

}  // namespace mtg::graph
