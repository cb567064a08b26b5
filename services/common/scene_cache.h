#pragma once
// Scenes and their graphs, loaded once per process and shared by all episodes on that scene.

#include <map>
#include <memory>
#include <string>

#include "core/graph/scene_graph.h"
#include "core/scene/mesh.h"

namespace mtg::services {

class SceneCache {
 public:
  explicit SceneCache(std::string profile = "replica_cad") : profile_(std::move(profile)) {}

  /// The graph of `scene` in the dataset at `data_dir` ("" = default search order).
  /// @throws mtg::Error if the scene cannot be loaded.
  const graph::SceneGraph& get(const std::string& scene, const std::string& data_dir);

 private:
  std::string profile_;
  scene::MeshCache meshes_{scene::MeshLoadOptions{.keep_textures = false}};
  std::map<std::string, std::unique_ptr<graph::SceneGraph>> graphs_;
};

}  // namespace mtg::services
