// `mtg bench pool`: rendered oracle episodes over the bus with pools of 1, 2, ... renderers
// (core/render/render_pool.h): episodes per second and per CPU-second of every process, whole
// and after the first result (scenes loaded, GPU copies made), and whether every observation's
// images are the same bytes whatever the pool. The pools alternate round by round, so a machine
// whose speed drifts hits each alike. Wall-clock and CPU here are telemetry only.

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <thread>
#include <vector>

#include "bus/channels.h"
#include "bus/observation_packing.h"
#include "bus/recording.h"
#include "bus/url.h"
#include "core/render/gl/gl_context.h"
#include "core/render/render_pool.h"
#include "core/tasks/job.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "core/util/parallel.h"
#include "mtg/observation_t.hpp"
#include "orchestrator/cli/bench_commands.h"
#include "orchestrator/run/process_memory.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_engine.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2.0;
}

double tree_cpu_seconds() {
  double total = 0.0;
  for (const auto& p : orchestrator::process_tree_memory(::getpid())) total += p.cpu_seconds;
  return total;
}

// (episode, step) -> its images' roles and content hashes, as the agent got them.
using ImagesSeen = std::map<std::pair<std::int64_t, int>, std::vector<std::string>>;

ImagesSeen images_seen(const fs::path& run) {
  ImagesSeen out;
  bus::RecordedObservations recorded;
  bus::for_each_recorded_event(run, [&](const lcm::LogEvent& ev) {
    if (!bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) return;
    mtg::observation_t packed{};
    if (packed.decode(ev.data, 0, ev.datalen) < 0) return;
    const auto whole = recorded.whole(packed);
    if (!whole || whole->n_images == 0) return;
    auto& hashes = out[{whole->header.episode_id, whole->step}];
    hashes.clear();
    for (const auto& img : whole->images) hashes.push_back(img.role + " " + img.content_hash);
  });
  return out;
}

struct PoolFigures {
  double episodes = 0, seconds = 0, cpu = 0;           // the whole invocation
  double steady_episodes = 0, steady_seconds = 0, steady_cpu = 0;  // from the first result on
};

}  // namespace

int run_bench_pool(const BenchPoolOptions& options) {
  const fs::path work = fresh_scratch_folder(options.work, "pool");
  const auto by_id = bench_task_set(work, options.scene, options.data_dir, options.per_level);
  const std::string tasks_db = (work / "tasks.sqlite").string();

  const int gpus = render::hardware_gl_devices();
  std::printf("renderer pool: oracle episodes with %dx%d PNG images on %s, Levels 1-3, %d tasks each, %d in flight, "
              "over %s; %d cores, %d GPU(s)%s\n",
              options.width, options.height, options.scene.c_str(), options.per_level, options.parallel,
              bus::default_url().c_str(), default_jobs(), gpus, gpus == 0 ? " (llvmpipe)" : "");
  for (const int n : options.renderers) {
    const auto pool = render::plan_render_pool(n, default_jobs(), gpus);
    std::printf("  %d renderer(s): %d encoder thread(s) each, %s\n", n, pool.front().encode_threads,
                gpus > 0 ? "one GPU each, round the GPUs"
                         : ("llvmpipe with " + std::to_string(pool.front().draw_threads) + " thread(s) each").c_str());
  }
  std::map<int, std::vector<PoolFigures>> figures;
  std::map<int, ImagesSeen> first_images;
  for (int round = 1; round <= options.rounds; ++round) {
    for (const int n : options.renderers) {
      const std::string name = "renderers-" + std::to_string(n) + "-round-" + std::to_string(round);
      orchestrator::RunPlan plan;
      plan.run_id = orchestrator::new_run_id(name);
      plan.tasks_db = tasks_db;
      plan.agents = {"oracle"};
      plan.levels = {1, 2, 3};
      plan.limit = options.per_level;
      plan.parallel = options.parallel;
      plan.render = true;
      plan.image_width = options.width;
      plan.image_height = options.height;
      plan.data_dir = options.data_dir;
      plan.bus_url = bus::normalize_url(bus::default_url());
      plan = orchestrator::make_plan(std::move(plan), by_id);
      const fs::path dir = work / name;
      fs::create_directories(dir);
      orchestrator::save_plan(plan, dir);
      std::atomic<std::int64_t> stored{0};
      orchestrator::EngineOptions engine;
      engine.progress = false;
      engine.renderers = n;
      engine.stored = &stored;
      // CPU of every process of the run, sampled at the first and at the last result.
      const auto planned = static_cast<std::int64_t>(plan.episodes.size());
      PoolFigures f;
      double cpu_first = 0, cpu_last = 0;
      std::int64_t at_first = 0;
      Clock::time_point t_first{}, t_last{};
      const orchestrator::RunSummary summary =
          run_plan_sampled(plan, dir, by_id, engine, [&](const std::atomic<bool>& done) {
            while (!done) {
              const std::int64_t now = stored.load();
              if (at_first == 0 && now > 0) {
                cpu_first = tree_cpu_seconds();
                t_first = Clock::now();
                at_first = now;
              }
              if (now >= planned && t_last == Clock::time_point{}) {
                cpu_last = tree_cpu_seconds();
                t_last = Clock::now();
              }
              std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
          });
      f.episodes = static_cast<double>(summary.completed);
      f.seconds = summary.seconds;
      f.cpu = summary.cpu_seconds;
      if (at_first > 0 && t_last != Clock::time_point{}) {
        f.steady_episodes = static_cast<double>(planned - at_first);
        f.steady_seconds = std::chrono::duration<double>(t_last - t_first).count();
        f.steady_cpu = cpu_last - cpu_first;
      }
      long succeeded = 0;
      for (const auto& row : orchestrator::read_results(dir / "results.sqlite")) succeeded += row.success ? 1 : 0;
      std::printf("  round %d, %d renderer(s): %.0f episodes (%ld succeeded) in %.1f s = %.2f episodes/s, %.3f per "
                  "CPU-second (%.0f CPU-s); after the first result %.2f episodes/s, %.3f per CPU-second\n",
                  round, n, f.episodes, succeeded, f.seconds, f.episodes / f.seconds, f.episodes / f.cpu, f.cpu,
                  f.steady_seconds > 0 ? f.steady_episodes / f.steady_seconds : 0.0,
                  f.steady_cpu > 0 ? f.steady_episodes / f.steady_cpu : 0.0);
      std::fflush(stdout);
      figures[n].push_back(f);
      if (round == 1) first_images[n] = images_seen(dir);
    }
  }
  for (const int n : options.renderers) {
    std::vector<double> rate, per_cpu, steady, steady_cpu;
    for (const PoolFigures& f : figures[n]) {
      rate.push_back(f.episodes / f.seconds);
      per_cpu.push_back(f.episodes / f.cpu);
      if (f.steady_seconds > 0) steady.push_back(f.steady_episodes / f.steady_seconds);
      if (f.steady_cpu > 0) steady_cpu.push_back(f.steady_episodes / f.steady_cpu);
    }
    std::printf("  %d renderer(s), median of %d: %.2f episodes/s, %.3f per CPU-second; after the first result %.2f "
                "episodes/s, %.3f per CPU-second\n",
                n, options.rounds, median(rate), median(per_cpu), median(steady), median(steady_cpu));
  }
  // The same episodes, the same images, whatever the pool (compared with the first pool's).
  const int base = options.renderers.front();
  for (const int n : options.renderers) {
    if (n == base) continue;
    const ImagesSeen& a = first_images[base];
    const ImagesSeen& b = first_images[n];
    std::size_t same = 0;
    for (const auto& [key, hashes] : a) {
      const auto it = b.find(key);
      same += it != b.end() && it->second == hashes ? 1 : 0;
    }
    std::printf("  images, %d against %d renderer(s): %zu of %zu observations identical%s\n", n, base, same, a.size(),
                same == a.size() && a.size() == b.size() ? " (every byte)" : "  <-- DIFFERENT");
  }
  std::printf("  runs kept in %s\n", work.c_str());
  return 0;
}

}  // namespace mtg::cli
