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

bool SceneGraph::called(const std::string& word, const std::string& noun) const {
  if (word == noun) return true;
  const auto it = noun_covers.find(word);
  return it != noun_covers.end() && it->second.count(noun) != 0;
}

std::vector<std::string> SceneGraph::words_covering(const std::string& noun) const {
  std::vector<std::string> out;
  for (const auto& [word, nouns] : noun_covers) {
    if (nouns.count(noun) != 0) out.push_back(word);
  }
  return out;
}

ObjectId SceneGraph::find_object(const std::string& name) const {
  for (const ObjectId o : objects.ids()) {
    if (objects[o].name == name) return o;
  }
  return {};
}

PlatformId SceneGraph::find_platform(const std::string& name) const {
  for (const PlatformId p : platforms.ids()) {
    if (platforms[p].name == name) return p;
  }
  return {};
}

std::vector<ObjectId> SceneGraph::pickable_on(PlatformId platform) const {
  return pickable_on(platform, [this](PlatformId p) -> const std::vector<ObjectId>& { return platforms.at(p).items; });
}

}  // namespace mtg::graph
