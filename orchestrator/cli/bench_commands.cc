#include "orchestrator/cli/bench_commands.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "core/episode/placement.h"
#include "core/graph/build.h"
#include "core/render/visibility.h"
#include "core/scene/scene_loader.h"
#include "core/tasks/atomic.h"
#include "core/tasks/generator.h"
#include "core/tasks/job.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "core/util/file_bytes.h"
#include "core/util/parallel.h"
#include "core/util/sha256.h"
#include "core/util/stopwatch.h"

namespace mtg::cli {
namespace {

struct Series {
  std::vector<double> ms;
  double min() const { return *std::min_element(ms.begin(), ms.end()); }
  double median() const {
    std::vector<double> s = ms;
    std::sort(s.begin(), s.end());
    return s[s.size() / 2];
  }
};

}  // namespace

std::map<std::string, tasks::Task> bench_task_set(const std::filesystem::path& work, const std::string& scene,
                                                  const std::string& data_dir, int per_level) {
  tasks::GenerationJob job;
  job.scenes = {scene};
  job.data_dir = data_dir;
  job.out = (work / "tasks.sqlite").string();
  job.options.levels = {1, 2, 3};
  job.options.level3_count = std::max(1, per_level);
  tasks::run_generation(job);
  std::map<std::string, tasks::Task> by_id;
  for (auto& t : tasks::read_tasks(job.out)) by_id.emplace(t.id, std::move(t));
  return by_id;
}

orchestrator::RunSummary run_plan_sampled(const orchestrator::RunPlan& plan, const std::filesystem::path& dir,
                                          const std::map<std::string, tasks::Task>& tasks,
                                          const orchestrator::EngineOptions& engine,
                                          const std::function<void(const std::atomic<bool>& done)>& sampler) {
  std::atomic<bool> done{false};
  std::thread thread([&] { sampler(done); });
  orchestrator::RunSummary summary;
  try {
    summary = orchestrator::run_plan(plan, dir, tasks, engine);
  } catch (...) {
    done = true;
    thread.join();
    throw;
  }
  done = true;
  thread.join();
  return summary;
}

std::filesystem::path fresh_scratch_folder(const std::string& work_dir, const std::string& command) {
  namespace fs = std::filesystem;
  const fs::path work = fs::absolute(work_dir);
  const fs::path marker = work / (".mtg_bench_" + command);
  if (fs::exists(work) && !fs::is_empty(work) && !fs::exists(marker)) {
    throw Error(work.string() + " is not empty and not a scratch folder of mtg bench " + command + "; pass another --work");
  }
  fs::remove_all(work);
  fs::create_directories(work);
  std::ofstream(marker) << "scratch folder of mtg bench " << command << "; emptied on every run\n";
  return work;
}

int run_bench_scene_load(const BenchSceneLoadOptions& options) {
  const scene::Dataset dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  const scene::MeshLoadOptions mesh_options{.keep_textures = true};
  const int repeat = std::max(1, options.repeat);

  // Cold: the first load of this process (files read from disk unless the page cache holds them).
  scene::MeshCache first_cache(mesh_options);
  Stopwatch watch;
  const scene::Scene first = scene::load_scene(dataset, options.scene, first_cache);
  const double cold_ms = watch.elapsed_ms();

  Series fresh, cached;
  for (int i = 0; i < repeat; ++i) {
    scene::MeshCache cache(mesh_options);  // files are in the page cache; meshes parsed again
    watch.reset();
    scene::load_scene(dataset, options.scene, cache);
    fresh.ms.push_back(watch.elapsed_ms());
    watch.reset();
    scene::load_scene(dataset, options.scene, first_cache);  // meshes shared from the cache
    cached.ms.push_back(watch.elapsed_ms());
  }

  std::size_t triangles = 0;
  for (const auto& o : first.objects) triangles += o.render_triangles();
  std::printf("scene-load %s: %zu objects, %zu triangles, %d mesh files (textures kept)\n",
              options.scene.c_str(), first.objects.size(), triangles, first.stats.meshes_loaded);
  std::printf("  cold   first load in a new process              %8.1f ms\n", cold_ms);
  std::printf("  warm   new mesh cache, files in page cache      %8.1f ms min  %8.1f ms median (%d runs)\n",
              fresh.min(), fresh.median(), repeat);
  std::printf("  warm   shared mesh cache (service reload)       %8.1f ms min  %8.1f ms median (%d runs)\n",
              cached.min(), cached.median(), repeat);
  std::printf("  peak RSS                                        %8.1f MiB\n", peak_rss_mib());
  return 0;
}

int run_bench_scene_graph(const BenchSceneGraphOptions& options) {
  const scene::Dataset dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, graph::kDefaultProfile);
  const int repeat = std::max(1, options.repeat);
  std::printf("scene-graph (profile %s)       cold = load meshes + build, warm = build from a loaded scene\n",
              graph_options.profile_name.c_str());
  for (const std::string& name : options.scenes) {
    scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
    Stopwatch watch;
    const scene::Scene loaded = scene::load_scene(dataset, name, cache);
    const graph::SceneGraph first = graph::build_scene_graph(loaded, graph_options);
    const double cold_ms = watch.elapsed_ms();
    Series warm;
    graph::BuildTimings t;
    for (int i = 0; i < repeat; ++i) {
      watch.reset();
      graph::build_scene_graph(loaded, graph_options, &t);
      warm.ms.push_back(watch.elapsed_ms());
    }
    std::printf("  %-8s cold %7.1f ms   warm %6.1f ms min %6.1f ms median   (%zu platforms, %zu navigable;"
                " last: surfaces %.0f, settle %.0f, clearance %.0f, overlap %.0f, standing %.0f ms)\n",
                name.c_str(), cold_ms, warm.min(), warm.median(), first.platforms.size(),
                first.navigable.size(), t.platforms, t.settle, t.clearance, t.overlap, t.standing);
  }
  std::printf("  peak RSS %.1f MiB\n", peak_rss_mib());
  return 0;
}

int run_bench_tasks(const BenchTasksOptions& options) {
  const scene::Dataset dataset = scene::index_dataset(scene::resolve_data_root(options.data_dir));
  graph::GraphOptions graph_options;
  graph::apply_profile(graph_options, graph::kDefaultProfile);
  // The whole job first, so the peak RSS is that of `mtg tasks`, not of the timings after it.
  std::printf("tasks: all four levels (mtg tasks), the first apartment alone, then Levels 1+2 per apartment"
              " and Level 3 alone\n");
  tasks::GenerationJob job;
  job.scenes = options.scenes;
  job.data_dir = options.data_dir;
  job.out = options.out;
  job.jobs = default_jobs();
  std::printf("  all four levels on %d thread%s (mtg tasks' default):\n", job.jobs, job.jobs == 1 ? "" : "s");
  const auto report = tasks::run_generation(job);
  for (const auto& sc : report.scenes) {
    std::printf("  %-8s all levels: L1 %ld  L2 %ld  L3 %ld  L4 %ld  (%ld tasks, %.1f s incl. load + graph)\n",
                sc.scene.c_str(), static_cast<long>(sc.levels[0]), static_cast<long>(sc.levels[1]),
                static_cast<long>(sc.levels[2]), static_cast<long>(sc.levels[3]), static_cast<long>(sc.total), sc.seconds);
  }
  std::printf("  all four levels, %zu apartments: %ld tasks in %.1f s (database written), peak RSS %.0f MiB\n",
              options.scenes.size(), static_cast<long>(report.total), report.seconds, peak_rss_mib());
  const auto bytes = std::filesystem::file_size(options.out);
  // Builds compared must write the same bytes (the database is deterministic): its digest is
  // the line to compare between them.
  std::printf("  task database: %.1f MB, %.0f B per task, sha256 %s\n", static_cast<double>(bytes) / 1e6,
              static_cast<double>(bytes) / static_cast<double>(std::max<std::int64_t>(1, report.total)),
              sha256_hex(read_file_bytes(options.out)).substr(0, 16).c_str());
  // One apartment alone: above, the apartments shared the threads, so their own times overlap.
  tasks::GenerationJob alone = job;
  alone.scenes = {options.scenes.front()};
  alone.out = options.out + ".alone";
  const auto one = tasks::run_generation(alone);
  std::printf("  %-8s all levels alone: %ld tasks in %.1f s (load, graph, tasks, database) on %d thread%s\n",
              alone.scenes.front().c_str(), static_cast<long>(one.total), one.seconds, alone.jobs,
              alone.jobs == 1 ? "" : "s");
  std::filesystem::remove(alone.out);

  for (const std::string& name : options.scenes) {
    scene::MeshCache cache(scene::MeshLoadOptions{.keep_textures = false});
    const scene::Scene loaded = scene::load_scene(dataset, name, cache);
    const graph::SceneGraph g = graph::build_scene_graph(loaded, graph_options);
    const render::SceneGeometry geometry(loaded, g);
    const render::VisibilityOracle seeing(g, geometry);
    tasks::TaskOptions atomic;
    atomic.levels = {1, 2};
    Stopwatch watch;
    const auto r = tasks::generate_tasks(g, atomic, {}, {}, 1, {}, &seeing);
    std::printf("  %-8s L1+L2 %6zu tasks in %6.0f ms (graph built beforehand)\n", name.c_str(), r.set.tasks.size(),
                watch.elapsed_ms());
    if (name != options.scenes.front()) continue;
    // Level 3 alone (its atomic set included), on one thread and on every core.
    tasks::TaskOptions chains;
    chains.levels = {3};
    std::string first;
    for (const int jobs : {1, default_jobs()}) {
      Stopwatch l3;
      const auto c = tasks::generate_tasks(g, chains, {}, {}, jobs, {}, &seeing);
      const double ms = l3.elapsed_ms();
      std::string all;
      for (const auto& t : c.set.tasks) all += tasks::task_to_json(t).dump() + "\n";
      if (first.empty()) first = all;
      // The chains are drawn from the initial state's atomic tasks; `mtg tasks` enumerates those
      // once for Levels 1-3, so the drawing is also shown without them.
      Stopwatch enumeration;
      episode::PlacementMemo memo;
      tasks::enumerate_atomic(g, episode::initial_state(g), chains, {}, nullptr, jobs, &memo);
      const double atomic_ms = enumeration.elapsed_ms();
      std::printf("  %-8s L3 %zu chains in %6.0f ms on %d thread%s%s; drawing them from the atomic set %.0f ms\n",
                  name.c_str(), c.set.tasks.size(), ms, jobs, jobs == 1 ? "" : "s",
                  jobs == 1 ? "" : (all == first ? " (the same tasks)" : " (OTHER TASKS: a bug)"), ms - atomic_ms);
    }
  }
  return 0;
}

}  // namespace mtg::cli
