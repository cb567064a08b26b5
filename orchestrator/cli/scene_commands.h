#pragma once
// `mtg scene ...`: list the scenes of a dataset and summarise one.

#include <cstdint>
#include <string>

namespace mtg::cli {

struct SceneListOptions {
  std::string data_dir;  // "" = default search order
};

struct SceneInfoOptions {
  std::string scene;
  std::string data_dir;
  bool json = false;   // one JSON object on stdout instead of the human summary
  bool files = false;  // the scene's files that exist, relative to the dataset root, one a line
};

struct SceneGraphOptions {
  std::string scene;
  std::string data_dir;
  std::string out;              // graph.json path ("" = do not write)
  std::string png;              // top-down PNG path ("" = none)
  std::string profile = "replica_cad";
};

/// `mtg scene remix`: the scene with its items put elsewhere (episode/remix.h), written as a new
/// scene of a dataset folder that links to the original's files (only the scene file is new).
struct SceneRemixOptions {
  std::string scene;
  std::string data_dir;
  std::string profile = "replica_cad";
  std::uint64_t seed = 1;
  std::string name;  // the new scene's name ("" = <scene>_remix_<seed>)
  std::string out;   // the dataset folder to write (made, or added to)
};

int run_scene_list(const SceneListOptions& options);
int run_scene_remix(const SceneRemixOptions& options);
int run_scene_graph(const SceneGraphOptions& options);
int run_scene_info(const SceneInfoOptions& options);

}  // namespace mtg::cli
