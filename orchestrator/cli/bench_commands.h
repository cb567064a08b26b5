#pragma once
// `mtg bench ...`: the measurements scripts/bench prints (wall-clock, telemetry only).

#include <string>

namespace mtg::cli {

struct BenchSceneLoadOptions {
  std::string scene = "apt_0";
  std::string data_dir;
  int repeat = 5;
};

int run_bench_scene_load(const BenchSceneLoadOptions& options);

}  // namespace mtg::cli
