#include "core/scene/dataset.h"

#include <algorithm>
#include <cstdlib>

#include "core/util/error.h"
#include "core/util/json_file.h"

namespace mtg::scene {
namespace fs = std::filesystem;
namespace {

bool has_suffix(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Adds every file under `dir` (recursively) whose name ends with `suffix`, keyed by the name
// without the suffix. The first one found for a key wins; files are visited in sorted order.
void index_files(const fs::path& dir, const std::string& suffix,
                 std::map<std::string, fs::path>& out) {
  if (!fs::is_directory(dir)) return;
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file() && has_suffix(entry.path().filename().string(), suffix)) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::string name = f.filename().string();
    out.emplace(name.substr(0, name.size() - suffix.size()), f);
  }
}

// Directories named by a "paths" entry of the dataset config: plain folders, or "folder/*/"
// globs meaning every sub-folder.
std::vector<fs::path> config_dirs(const fs::path& root, const nlohmann::json& section,
                                  const std::string& ext) {
  std::vector<fs::path> dirs;
  if (!section.is_object() || !section.contains("paths")) return dirs;
  const auto& paths = section["paths"];
  if (!paths.is_object() || !paths.contains(ext) || !paths[ext].is_array()) return dirs;
  for (const auto& p : paths[ext]) {
    if (!p.is_string()) continue;
    std::string rel = p.get<std::string>();
    if (has_suffix(rel, "*/")) rel = rel.substr(0, rel.size() - 2);  // recursion covers children
    if (has_suffix(rel, "*")) rel = rel.substr(0, rel.size() - 1);
    const fs::path dir = root / rel;
    if (fs::is_directory(dir)) dirs.push_back(dir);
  }
  return dirs;
}

std::string common_prefix(const std::map<std::string, fs::path>& names) {
  if (names.size() < 2) return "";
  std::string prefix = names.begin()->first;
  for (const auto& [name, path] : names) {
    std::size_t n = 0;
    while (n < prefix.size() && n < name.size() && prefix[n] == name[n]) ++n;
    prefix.resize(n);
  }
  const auto cut = prefix.rfind('_');
  return cut == std::string::npos ? "" : prefix.substr(0, cut + 1);
}

}  // namespace

fs::path resolve_data_root(const std::string& explicit_dir) {
  if (!explicit_dir.empty()) {
    if (!fs::is_directory(explicit_dir)) {
      throw Error("data directory does not exist: " + explicit_dir);
    }
    return fs::absolute(explicit_dir).lexically_normal();
  }
  if (const char* env = std::getenv("MTG_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!fs::is_directory(env)) {
      throw Error(std::string("data directory does not exist: ") + env + " (from $MTG_DATA_DIR)");
    }
    return fs::absolute(env).lexically_normal();
  }
  // data/replica_cad beside the working directory or the source tree, then the shared dataset
  // folder (shared/datasets/replica_cad) next to either of them or one of their parents.
  const fs::path source(MTG_SOURCE_DIR);
  std::vector<fs::path> candidates = {fs::path("data/replica_cad"), source / "data/replica_cad"};
  for (fs::path base : {fs::current_path(), source}) {
    for (int up = 0; up < 4 && !base.empty(); ++up, base = base.parent_path()) {
      candidates.push_back(base / "../shared/datasets/replica_cad");
      if (base == base.parent_path()) break;
    }
  }
  std::string tried;
  for (const auto& c : candidates) {
    if (fs::is_directory(c)) return fs::absolute(c).lexically_normal();
    tried += (tried.empty() ? "" : ", ") + c.lexically_normal().string();
  }
  throw Error("no dataset found: set $MTG_DATA_DIR or pass --data (tried " + tried + ")");
}

std::string template_basename(const std::string& template_name) {
  const auto slash = template_name.find_last_of('/');
  return slash == std::string::npos ? template_name : template_name.substr(slash + 1);
}

std::vector<std::string> Dataset::scene_names() const {
  std::vector<std::string> names;
  for (const auto& [name, path] : scenes) names.push_back(name);
  return names;
}

const fs::path& Dataset::scene_file(const std::string& name) const {
  const auto it = scenes.find(name);
  if (it == scenes.end()) {
    std::string available;
    for (const auto& [n, p] : scenes) available += (available.empty() ? "" : ", ") + n;
    throw Error("unknown scene '" + name + "' in " + root.string() + " (available: " + available +
                ")");
  }
  return it->second;
}

std::string Dataset::short_name(const std::string& template_name) const {
  if (!object_prefix.empty() && template_name.size() > object_prefix.size() &&
      template_name.compare(0, object_prefix.size(), object_prefix) == 0) {
    return template_name.substr(object_prefix.size());
  }
  return template_name;
}

Dataset index_dataset(const fs::path& root) {
  if (!fs::is_directory(root)) throw Error("data directory does not exist: " + root.string());
  Dataset ds;
  ds.root = root;

  // The dataset config says where things are; without one, use ReplicaCAD's default layout.
  fs::path dataset_config;
  for (const auto& entry : fs::directory_iterator(root)) {
    if (has_suffix(entry.path().filename().string(), ".scene_dataset_config.json")) {
      dataset_config = entry.path();
      break;
    }
  }
  nlohmann::json config = nlohmann::json::object();
  if (!dataset_config.empty()) {
    config = read_json_file(dataset_config);
    ds.config_files.push_back(dataset_config);
  }

  auto dirs_or = [&](const char* section, const std::string& ext, const char* fallback) {
    auto dirs = config.contains(section) ? config_dirs(root, config[section], ext)
                                         : std::vector<fs::path>{};
    if (dirs.empty() && fs::is_directory(root / fallback)) dirs.push_back(root / fallback);
    return dirs;
  };
  for (const auto& d : dirs_or("scene_instances", ".json", "configs/scenes")) {
    index_files(d, ".scene_instance.json", ds.scenes);
  }
  for (const auto& d : dirs_or("objects", ".json", "configs/objects")) {
    index_files(d, ".object_config.json", ds.object_configs);
  }
  for (const auto& d : dirs_or("stages", ".json", "configs/stages")) {
    index_files(d, ".stage_config.json", ds.stage_configs);
  }
  for (const auto& d : dirs_or("articulated_objects", ".urdf", "urdf")) {
    index_files(d, ".urdf", ds.urdfs);
  }
  if (ds.scenes.empty()) {
    throw Error(root.string() + ": no *.scene_instance.json found (is this a ReplicaCAD-format "
                                "dataset root?)");
  }
  ds.object_prefix = common_prefix(ds.object_configs);

  // Semantic lexicon: class names for categories ("book", "table", ...).
  if (config.contains("semantic_scene_descriptor_instances") &&
      config["semantic_scene_descriptor_instances"].is_object()) {
    for (const auto& item : config["semantic_scene_descriptor_instances"].items()) {
      if (!item.value().is_string()) continue;
      const fs::path lexicon = root / item.value().get<std::string>();
      if (!fs::exists(lexicon)) continue;
      const nlohmann::json j = read_json_file(lexicon);
      ds.config_files.push_back(lexicon);
      const JsonField classes = JsonField(j, lexicon.string()).at("classes");
      for (std::size_t i = 0; i < classes.size(); ++i) {
        const JsonField c = classes.at(i);
        ds.semantic_classes[static_cast<int>(c.at("id").as_double())] = c.at("name").as_string();
      }
    }
  }
  return ds;
}

}  // namespace mtg::scene
