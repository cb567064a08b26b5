#pragma once
// `mtg bench ...`: the measurements scripts/bench prints (wall-clock, telemetry only).

#include <string>
#include <vector>

namespace mtg::cli {

struct BenchSceneLoadOptions {
  std::string scene = "apt_0";
  std::string data_dir;
  int repeat = 5;
};

struct BenchSceneGraphOptions {
  std::vector<std::string> scenes = {"apt_0", "apt_1", "apt_2"};
  std::string data_dir;
  int repeat = 5;
};

struct BenchTasksOptions {
  std::vector<std::string> scenes = {"apt_0", "apt_1", "apt_2"};
  std::string data_dir;
  std::string out = "/tmp/mtg_bench_tasks.sqlite";
};

int run_bench_scene_load(const BenchSceneLoadOptions& options);
int run_bench_tasks(const BenchTasksOptions& options);
int run_bench_scene_graph(const BenchSceneGraphOptions& options);

}  // namespace mtg::cli
