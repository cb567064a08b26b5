#include "core/graph/scene_cache.h"

#include "core/graph/build.h"
#include "core/scene/scene_loader.h"
#include "core/util/log.h"
#include "core/util/parallel.h"

namespace mtg::graph {

const SceneCache::Entry& SceneCache::load(const std::string& scene_name, const std::string& data_dir) {
  const std::string key = data_dir + "|" + scene_name;
  auto it = entries_.find(key);
  if (it == entries_.end()) {
    const auto dataset = scene::index_dataset(scene::resolve_data_root(data_dir));
    auto e = std::make_unique<Entry>();
    e->key = key;
    e->scene = scene::load_scene(dataset, scene_name, meshes_, {.jobs = default_jobs()});
    graph::GraphOptions options;
    graph::apply_profile(options, profile_);
    options.platform_rules = rules_;
    e->graph = graph::build_scene_graph(e->scene, options);
    log::info("loaded scene " + scene_name + ": " + std::to_string(e->graph.navigable.size()) +
              " navigable platforms");
    it = entries_.emplace(key, std::move(e)).first;
  }
  return *it->second;
}

}  // namespace mtg::graph
