#include "orchestrator/cli/scene_commands.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "core/episode/remix.h"
#include "core/graph/build.h"
#include "core/graph/graph_json.h"
#include "core/graph/topdown_png.h"
#include "core/scene/dataset.h"
#include "core/util/error.h"
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

int run_scene_remix(const SceneRemixOptions& o) {
  namespace fs = std::filesystem;
  if (o.out.empty()) throw Error("mtg scene remix: --out <dataset folder> is required");
  const auto dataset = scene::index_dataset(scene::resolve_data_root(o.data_dir));
  const fs::path root = dataset.root;
  const std::string name = o.name.empty() ? o.scene + "_remix_" + std::to_string(o.seed) : o.name;
  const fs::path out(o.out);
  if (fs::exists(out) && fs::canonical(out) == fs::canonical(root)) {
    throw Error("mtg scene remix: --out is the dataset itself (" + root.string() + "); give another folder");
  }
  const fs::path file = out / "configs" / "scenes" / (name + ".scene_instance.json");
  if (fs::exists(file)) throw Error("mtg scene remix: " + file.string() + " exists already");
  scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
  const scene::Scene loaded = scene::load_scene(dataset, o.scene, cache, {.jobs = default_jobs()});
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, o.profile);
  const graph::SceneGraph g = graph::build_scene_graph(loaded, graph_options);
  const std::map<std::string, Eigen::Vector3d> moved = episode::remix_items(g, o.seed);

  // The scene file with each moved item's translation shifted (the file is Y-up: (x, y, z) in the
  // world is (x, z, -y) there).
  nlohmann::json doc = read_json_file(dataset.scene_file(o.scene));
  nlohmann::json& instances = doc.at("object_instances");
  for (const scene::ObjectInstance& obj : loaded.objects) {
    const auto it = moved.find(obj.name);
    if (it == moved.end() || obj.articulated) continue;
    nlohmann::json& t = instances.at(static_cast<std::size_t>(obj.file_index)).at("translation");
    const Eigen::Vector3d d = it->second;
    t = {t.at(0).get<double>() + d.x(), t.at(1).get<double>() + d.z(), t.at(2).get<double>() - d.y()};
  }
  // A dataset folder whose every entry but the scenes links to the original.
  fs::create_directories(out / "configs" / "scenes");
  auto link = [](const fs::path& target, const fs::path& at) {
    if (!fs::exists(fs::symlink_status(at))) fs::create_directory_symlink(target, at);
  };
  for (const auto& e : fs::directory_iterator(root)) {
    const fs::path at = out / e.path().filename();
    if (e.path().filename() == "configs") continue;
    if (fs::exists(fs::symlink_status(at))) continue;
    if (e.is_directory()) {
      fs::create_directory_symlink(e.path(), at);
    } else {
      fs::create_symlink(e.path(), at);
    }
  }
  for (const auto& e : fs::directory_iterator(root / "configs")) {
    if (e.path().filename() != "scenes" && e.is_directory()) link(e.path(), out / "configs" / e.path().filename());
  }
  write_json_file(file, doc);
  std::printf("wrote %s: %s with %zu objects moved (seed %llu)\nuse it with --data %s --scene %s\n", file.c_str(),
              o.scene.c_str(), moved.size(), static_cast<unsigned long long>(o.seed), out.c_str(), name.c_str());
  return 0;
}

}  // namespace mtg::cli
