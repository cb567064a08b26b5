#include "orchestrator/cli/scene_commands.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/graph/build.h"
#include "core/graph/graph_json.h"
#include "core/graph/topdown_png.h"
#include "core/scene/dataset.h"
#include "core/util/json_file.h"
#include "core/scene/scene_loader.h"
#include "core/scene/scene_summary.h"
#include "core/util/log.h"
#include "core/util/parallel.h"

namespace mtg::cli {

int run_scene_list(const SceneListOptions& options) {
  const auto dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  for (const auto& name : dataset.scene_names()) std::cout << name << '\n';
  return 0;
}

int run_scene_info(const SceneInfoOptions& options) {
  const auto dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
  const scene::Scene loaded = scene::load_scene(dataset, options.scene, cache, {.jobs = default_jobs()});
  if (options.files) {
    for (const std::filesystem::path& f : scene::files_to_copy(dataset, loaded)) {
      std::cout << f.lexically_relative(dataset.root).string() << '\n';
    }
    return 0;
  }
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

int run_scene_graph(const SceneGraphOptions& options) {
  const auto dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
  const scene::Scene loaded = scene::load_scene(dataset, options.scene, cache, {.jobs = default_jobs()});
  for (const auto& w : loaded.warnings) log::warn(w);
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, options.profile);
  graph::BuildTimings timings;
  const graph::SceneGraph g = graph::build_scene_graph(loaded, graph_options, &timings);
  for (const auto& w : g.warnings) log::warn(w);
  const nlohmann::json summary = graph::graph_summary(g);
  std::printf("scene graph   %s: %d platforms (%d destinations), %d navigable (l1..l%d)\n",
              g.scene.c_str(), summary["platforms"].get<int>(), summary["destinations"].get<int>(),
              summary["navigable"].get<int>(), summary["navigable"].get<int>());
  std::string kinds;
  for (const auto& [kind, n] : summary["by_kind"].items()) {
    kinds += (kinds.empty() ? "" : ", ") + kind + " " + std::to_string(n.get<int>());
  }
  std::printf("objects       %s\n", kinds.c_str());
  std::printf("pickable      %d items on navigable platforms\n",
              summary["pickable_on_navigable"].get<int>());
  std::printf("time          %.0f ms load + %.0f ms graph\n", loaded.stats.load_ms, timings.total);
  if (!options.out.empty()) {
    write_json_file(options.out, graph::graph_to_json(g, graph_options));
    std::printf("wrote         %s\n", options.out.c_str());
  }
  if (!options.png.empty()) {
    graph::write_topdown_png(g, options.png);
    std::printf("wrote         %s\n", options.png.c_str());
  }
  return 0;
}

}  // namespace mtg::cli
