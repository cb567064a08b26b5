#pragma once
// Scenes and their graphs, loaded once per process and shared by all episodes on that scene.

#include <map>
#include <memory>
#include <string>

#include "core/graph/options.h"
#include "core/graph/scene_graph.h"
#include "core/scene/mesh.h"
#include "core/scene/scene.h"

namespace mtg::graph {

class SceneCache {
 public:
  /// `with_textures`: keep the meshes' embedded textures (the renderer draws them; geometry
  /// does not need them and loads faster without).
  /// `rules`: as the tasks run on it were planned (tasks::platform_rules_of_format).
  explicit SceneCache(std::string profile = "replica_cad", PlatformRules rules = PlatformRules::kReachedAndSeen,
                      bool with_textures = false)
      : profile_(std::move(profile)), rules_(rules), meshes_(scene::MeshLoadOptions{.keep_textures = with_textures}) {}

  struct Entry {
    std::string key;  // data dir and scene name: stable identity for per-scene caches
    scene::Scene scene;
    graph::SceneGraph graph;
  };
  /// The scene `scene` in the dataset at `data_dir` ("" = default search order) and its graph.
  /// @throws mtg::Error if the scene cannot be loaded.
  const Entry& load(const std::string& scene, const std::string& data_dir);
  const graph::SceneGraph& get(const std::string& scene, const std::string& data_dir) {
    return load(scene, data_dir).graph;
  }

 private:
  std::string profile_;
  PlatformRules rules_;
  scene::MeshCache meshes_;
  std::map<std::string, std::unique_ptr<Entry>> entries_;
};

}  // namespace mtg::graph
