#pragma once
// `mtg bench ...`: the measurements scripts/bench prints (wall-clock, telemetry only).

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <filesystem>
#include <string>
#include <vector>

#include "core/tasks/task.h"
#include "orchestrator/run/run_engine.h"
#include "orchestrator/run/run_plan.h"

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

struct BenchRuntimeOptions {
  std::string scene = "apt_0";
  std::string data_dir;
  std::string work = "/tmp/mtg_bench_runtime";  // tasks and one run folder per parallelism and round
  int per_level = 200;                          // tasks per level, Levels 1-3
  std::vector<int> parallel = {1, 2, 4};
  int rounds = 3;  // the parallelisms alternate this many times: a drifting machine hits all alike
};

struct BenchRenderOptions {
  std::string scene = "apt_0";
  std::string data_dir;
  std::string profile = "replica_cad";
  int rounds = 3;     // passes over every navigable platform, per image size
  int episodes = 20;  // oracle episodes rendered end to end
};

struct BenchPoolOptions {
  std::string scene = "apt_0";
  std::string data_dir;
  std::string work = "/tmp/mtg_bench_pool";  // tasks and one run folder per pool and round
  int per_level = 10;                        // tasks per level, Levels 1-3
  int parallel = 4;                          // episodes in flight
  std::vector<int> renderers = {1, 2};       // the pools compared
  int rounds = 2;
  int width = 640;
  int height = 480;
};

struct BenchSoakOptions {
  std::string scene = "apt_0";   // tasks generated for it (Levels 1-4) unless --tasks
  std::string tasks;             // a task database to take instead
  std::string data_dir;
  std::string work = "/tmp/mtg_bench_soak";  // tasks and the run folder (emptied first)
  std::int64_t episodes = 1000000;
  std::vector<std::string> agents = {"oracle", "random"};
  std::string levels = "1,2,3,4";
  int parallel = 4;
  bool render = false;
  double every_s = 60.0;  // a row at least this often, besides every 100,000 episodes
  std::string json;       // also write the samples here
};

int run_bench_soak(const BenchSoakOptions& options);

/// Levels 1-3 of `scene` (`per_level` Level 3 tasks) generated into `work`/tasks.sqlite, by id.
std::map<std::string, tasks::Task> bench_task_set(const std::filesystem::path& work, const std::string& scene,
                                                  const std::string& data_dir, int per_level);

/// run_plan() with `sampler(done)` on a thread of its own until the run returns (or throws):
/// the benches watch a run's processes while it goes.
orchestrator::RunSummary run_plan_sampled(const orchestrator::RunPlan& plan, const std::filesystem::path& dir,
                                          const std::map<std::string, tasks::Task>& tasks,
                                          const orchestrator::EngineOptions& engine,
                                          const std::function<void(const std::atomic<bool>& done)>& sampler);

/// `work` (absolute), emptied and marked as the scratch folder of `mtg bench <command>`. A folder
/// that holds anything and is not such a scratch folder is never emptied.
/// @throws mtg::Error naming the folder then.
std::filesystem::path fresh_scratch_folder(const std::string& work, const std::string& command);
int run_bench_render(const BenchRenderOptions& options);
int run_bench_pool(const BenchPoolOptions& options);
int run_bench_scene_load(const BenchSceneLoadOptions& options);
int run_bench_tasks(const BenchTasksOptions& options);
int run_bench_scene_graph(const BenchSceneGraphOptions& options);
int run_bench_runtime(const BenchRuntimeOptions& options);

}  // namespace mtg::cli
