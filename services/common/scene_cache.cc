#include "services/common/scene_cache.h"

#include "core/graph/build.h"
#include "core/scene/scene_loader.h"
#include "core/util/log.h"

namespace mtg::services {

const graph::SceneGraph& SceneCache::get(const std::string& scene_name, const std::string& data_dir) {
  const std::string key = data_dir + "|" + scene_name;
  auto it = graphs_.find(key);
  if (it == graphs_.end()) {
    const auto dataset = scene::index_dataset(scene::resolve_data_root(data_dir));
    const scene::Scene loaded = scene::load_scene(dataset, scene_name, meshes_);
    graph::GraphOptions options;
    graph::apply_profile(options, profile_);
    auto g = std::make_unique<graph::SceneGraph>(graph::build_scene_graph(loaded, options));
    log::info("loaded scene " + scene_name + ": " + std::to_string(g->navigable.size()) + " navigable platforms");
    it = graphs_.emplace(key, std::move(g)).first;
  }
  return *it->second;
}

}  // namespace mtg::services
