#pragma once
// Loading one scene instance of a ReplicaCAD-format dataset into a typed Scene.

#include <filesystem>
#include <string>
#include <vector>

#include "core/scene/dataset.h"
#include "core/scene/mesh.h"
#include "core/scene/scene.h"

namespace mtg::scene {

struct SceneLoadOptions {
  bool load_meshes = true;  // false: poses and receptacles only (fast listing)
  int jobs = 1;             // threads reading the mesh files into the cache before the scene is put together
};

/// Loads `scene_name` from `dataset`, reading meshes through `cache`.
/// Missing or broken mesh files, unknown templates and URDFs that do not parse become one
/// warning each in Scene::warnings (with a fallback or the object skipped), never a crash.
/// @throws mtg::Error for an unknown scene or a malformed scene/config JSON (file + JSON path).
Scene load_scene(const Dataset& dataset, const std::string& scene_name, MeshCache& cache,
                 const SceneLoadOptions& options = {});

/// The files a copy of `dataset` needs to load `scene` as it loaded here, sorted: the dataset's
/// config files and the scene's sources that exist (`mtg scene info --files`, scripts/gpu-bundle).
std::vector<std::filesystem::path> files_to_copy(const Dataset& dataset, const Scene& scene);

}  // namespace mtg::scene
