#include "orchestrator/cli/scene_commands.h"

#include <cstdio>
#include <iostream>

#include "core/scene/dataset.h"
#include "core/scene/scene_loader.h"
#include "core/scene/scene_summary.h"
#include "core/util/log.h"

namespace mtg::cli {

int run_scene_list(const SceneListOptions& options) {
  const auto dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  for (const auto& name : dataset.scene_names()) std::cout << name << '\n';
  return 0;
}

int run_scene_info(const SceneInfoOptions& options) {
  const auto dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
  const scene::Scene loaded = scene::load_scene(dataset, options.scene, cache);
  const nlohmann::json summary = scene::summarize_scene(loaded);
  if (options.json) {
    std::cout << summary.dump() << '\n';
    return 0;
  }
  for (const auto& w : loaded.warnings) log::warn(w);
  std::printf("scene         %s (%s)\n", loaded.name.c_str(), loaded.scene_file.string().c_str());
  std::printf("objects       %d (%d rigid, %d articulated)\n", summary["objects"].get<int>(),
              summary["rigid"].get<int>(), summary["articulated"].get<int>());
  std::string motion;
  for (const auto& [type, n] : summary["by_motion_type"].items()) {
    motion += (motion.empty() ? "" : ", ") + type + " " + std::to_string(n.get<int>());
  }
  std::printf("motion types  %s\n", motion.c_str());
  std::printf("receptacles   %d declared\n", summary["receptacles"].get<int>());
  std::printf("meshes        %d loaded, %d missing\n", summary["meshes_loaded"].get<int>(),
              summary["meshes_missing"].get<int>());
  std::printf("triangles     %zu\n", summary["triangles"].get<std::size_t>());
  if (summary.contains("bounds")) {
    const auto& b = summary["bounds"];
    std::printf("bounds        [%.2f %.2f %.2f] .. [%.2f %.2f %.2f] m\n", b["min"][0].get<double>(),
                b["min"][1].get<double>(), b["min"][2].get<double>(), b["max"][0].get<double>(),
                b["max"][1].get<double>(), b["max"][2].get<double>());
  }
  std::printf("stage mesh    %s\n", loaded.stage_mesh_present ? "present" : "absent (walls unknown)");
  std::printf("load time     %.0f ms\n", loaded.stats.load_ms);
  return 0;
}

}  // namespace mtg::cli
