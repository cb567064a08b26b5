#pragma once
// Finding the dataset and indexing it the way its scene_dataset_config.json describes it:
// where scene instances, object configs, stages and URDFs live, and the semantic lexicon.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mtg::scene {

/// Where the data comes from, in this order: `explicit_dir` (a --data flag), $MTG_DATA_DIR,
/// ./data/replica_cad, <source>/data/replica_cad, then ../shared/datasets/replica_cad relative to
/// the working directory or the source tree or up to three of their parents.
/// @throws mtg::Error if an explicitly given directory does not exist, or if none is found
/// (the message lists every place tried).
std::filesystem::path resolve_data_root(const std::string& explicit_dir = "");

struct Dataset {
  std::filesystem::path root;
  std::map<std::string, std::filesystem::path> scenes;          // name -> *.scene_instance.json
  std::map<std::string, std::filesystem::path> object_configs;  // template -> *.object_config.json
  std::map<std::string, std::filesystem::path> stage_configs;   // template -> *.stage_config.json
  std::map<std::string, std::filesystem::path> urdfs;           // template (file stem) -> *.urdf
  std::map<int, std::string> semantic_classes;                  // lexicon id -> class name
  std::string object_prefix;  // common prefix of object templates, e.g. "frl_apartment_"
  std::vector<std::filesystem::path> config_files;  // the dataset config and lexicons read (not a scene's)

  std::vector<std::string> scene_names() const;
  /// @throws mtg::Error "unknown scene 'x' (available: a, b, ...)".
  const std::filesystem::path& scene_file(const std::string& name) const;
  /// Template name without the common prefix ("frl_apartment_table_02" -> "table_02").
  std::string short_name(const std::string& template_name) const;
};

/// Indexes a dataset root. @throws mtg::Error if the directory is missing, a config file is
/// malformed, or no scene instance is found.
Dataset index_dataset(const std::filesystem::path& root);

/// "objects/frl_apartment_basket" -> "frl_apartment_basket" (templates may carry a folder).
std::string template_basename(const std::string& template_name);

}  // namespace mtg::scene
