#pragma once
// `mtg scene ...`: list the scenes of a dataset and summarise one.

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

int run_scene_list(const SceneListOptions& options);
int run_scene_graph(const SceneGraphOptions& options);
int run_scene_info(const SceneInfoOptions& options);

}  // namespace mtg::cli
