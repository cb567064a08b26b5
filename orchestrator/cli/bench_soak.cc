// `mtg bench soak`: a long run of one orchestrator and one set of processes, printing every
// process's resident memory as the episodes go by, the episodes per second and the bytes
// recorded per episode (issue 37; docs/runtime.md "What each process keeps"). The question it
// answers: does anything grow with the number of episodes? The episodes are the run's tasks
// repeated (`--repeat`), so a million episodes need no million tasks.

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "bus/url.h"
#include "core/tasks/generator.h"
#include "core/tasks/job.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "orchestrator/cli/bench_commands.h"
#include "orchestrator/run/process_memory.h"
#include "orchestrator/run/run_engine.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Sample {
  std::int64_t episodes = 0;
  double seconds = 0.0;
  std::map<std::string, double> rss_mib;  // by role; the bench process itself is "orchestrator"
};

Sample sample(std::int64_t episodes, double seconds) {
  Sample s{episodes, seconds, {}};
  for (const auto& p : orchestrator::process_tree_memory(::getpid())) {
    s.rss_mib[p.role == "mtg" ? "orchestrator" : p.role] += p.rss_mib;
  }
  return s;
}

void print_header(const Sample& s) {
  std::printf("  %10s %8s %7s", "episodes", "time", "ep/s");
  for (const auto& [role, mib] : s.rss_mib) std::printf(" %13s", role.c_str());
  std::printf("   (RSS, MiB)\n");
}

void print_row(const Sample& s, const Sample* previous, const char* mark) {
  const double rate = previous != nullptr && s.seconds > previous->seconds
                          ? static_cast<double>(s.episodes - previous->episodes) / (s.seconds - previous->seconds)
                          : 0.0;
  std::printf("  %10lld %7.0fs %7.0f", static_cast<long long>(s.episodes), s.seconds, rate);
  for (const auto& [role, mib] : s.rss_mib) std::printf(" %13.1f", mib);
  std::printf("%s\n", mark);
  std::fflush(stdout);
}

}  // namespace

int run_bench_soak(const BenchSoakOptions& options) {
  if (options.episodes < 10) throw Error("--episodes must be at least 10");
  const fs::path work = fresh_scratch_folder(options.work, "soak");

  std::string tasks_db = options.tasks;
  if (tasks_db.empty()) {
    tasks::GenerationJob job;
    job.scenes = {options.scene};
    job.data_dir = options.data_dir;
    job.out = (work / "tasks.sqlite").string();
    job.options.levels = {1, 2, 3, 4};
    tasks::run_generation(job);
    tasks_db = job.out;
  }
  std::map<std::string, tasks::Task> by_id;
  for (auto& t : tasks::read_tasks(tasks_db)) by_id.emplace(t.id, std::move(t));

  orchestrator::RunPlan plan;
  plan.run_id = orchestrator::new_run_id("soak");
  plan.tasks_db = fs::absolute(tasks_db).string();
  plan.agents = options.agents;
  plan.levels = tasks::parse_levels(options.levels);
  plan.parallel = options.parallel;
  plan.render = options.render;
  plan.data_dir = options.data_dir;
  plan.bus_url = bus::normalize_url(bus::default_url());
  const std::size_t once = orchestrator::make_plan(plan, by_id).episodes.size();
  plan.repeat = static_cast<int>((static_cast<std::size_t>(options.episodes) + once - 1) / once);
  plan = orchestrator::make_plan(std::move(plan), by_id);
  plan.episodes.resize(static_cast<std::size_t>(options.episodes));
  const fs::path dir = work / "run";
  fs::create_directories(dir);
  orchestrator::save_plan(plan, dir);

  // The reference point: the first 10,000 episodes (a fifth of a shorter soak); then a
  // row every 100,000 (a tenth), and one every --every seconds.
  const std::int64_t first = std::min<std::int64_t>(10000, options.episodes / 5);
  const std::int64_t stride = options.episodes >= 1000000 ? 100000 : std::max<std::int64_t>(1, options.episodes / 10);
  std::printf("soak: %lld %s episodes (%zu tasks x %zu agents, repeated %d times; levels %s), %d in flight, over %s\n",
              static_cast<long long>(options.episodes), options.render ? "rendered" : "text-only", once / plan.agents.size(),
              plan.agents.size(), plan.repeat, options.levels.c_str(), plan.parallel, plan.bus_url.c_str());
  std::fflush(stdout);

  std::atomic<std::int64_t> stored{0};
  std::vector<Sample> samples;  // every row printed
  std::optional<Sample> reference;
  const auto started = Clock::now();
  orchestrator::EngineOptions engine;
  engine.progress = false;
  engine.stored = &stored;
  // The last row while the processes still live is the sampler's last; one more after the end
  // would find them gone.
  const orchestrator::RunSummary summary = run_plan_sampled(plan, dir, by_id, engine, [&](const std::atomic<bool>& done) {
    std::int64_t next_mark = first;
    auto next_time = started + std::chrono::duration<double>(options.every_s);
    bool header = false;
    while (!done) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      const std::int64_t n = stored.load(std::memory_order_relaxed);
      const auto now = Clock::now();
      const bool mark = n >= next_mark;
      if (!mark && now < next_time) continue;
      const Sample s = sample(n, std::chrono::duration<double>(now - started).count());
      if (!header) {
        print_header(s);
        header = true;
      }
      const char* note = "";
      if (mark && !reference) {
        reference = s;
        note = "   <- reference";
      }
      print_row(s, samples.empty() ? nullptr : &samples.back(), note);
      samples.push_back(s);
      while (next_mark <= n) next_mark = next_mark == first ? stride * ((first / stride) + 1) : next_mark + stride;
      next_time = now + std::chrono::duration<double>(options.every_s);
    }
  });

  std::uintmax_t recorded = 0;
  for (const auto& f : fs::directory_iterator(dir)) {
    if (f.path().extension() == ".lcmlog") recorded += f.file_size();
  }
  const double per_episode = summary.completed > 0 ? static_cast<double>(recorded) / static_cast<double>(summary.completed) : 0.0;
  const double rate = summary.episode_seconds > 0 ? static_cast<double>(summary.completed) / summary.episode_seconds : 0.0;
  // Every process is compared at one moment while the run still ran: the last row in which all of
  // the reference's processes were alive (a row taken as the run closes sees the services gone
  // and the orchestrator in the middle of shutting down). The bound, +10 MiB from 10,000
  // to 1,000,000 episodes, in proportion to the episodes between the two rows.
  const auto running = std::find_if(samples.rbegin(), samples.rend(), [&](const Sample& s) {
    return reference && std::all_of(reference->rss_mib.begin(), reference->rss_mib.end(),
                                     [&](const auto& r) { return s.rss_mib.count(r.first) != 0; });
  });
  const Sample last = running == samples.rend() ? Sample{} : *running;
  const double bound = reference ? 10.0 * static_cast<double>(last.episodes - reference->episodes) / 990000.0 : 0.0;
  std::printf("  %lld episodes in %.1f s: %.1f episodes/s, %lld retries; recorded %.1f MB = %.0f bytes per episode\n",
              static_cast<long long>(summary.completed), summary.episode_seconds, rate,
              static_cast<long long>(summary.retries), static_cast<double>(recorded) / 1e6, per_episode);
  nlohmann::json growth = nlohmann::json::object();
  if (reference) {
    std::printf("  growth from %lld to %lld episodes, the last row with every process running (bound in proportion "
                "to +10 MiB per 990,000: %.2f MiB):\n",
                static_cast<long long>(reference->episodes), static_cast<long long>(last.episodes), bound);
    for (const auto& [role, was] : reference->rss_mib) {
      const double mib = last.rss_mib.at(role);
      growth[role] = mib - was;
      std::printf("    %-16s %8.1f -> %8.1f MiB  %+6.2f MiB\n", role.c_str(), was, mib, mib - was);
    }
  }
  if (!options.json.empty()) {
    nlohmann::json out = {{"episodes", summary.completed},     {"episodes_per_s", rate},
                          {"bytes_per_episode", per_episode}, {"retries", summary.retries},
                          {"bound_mib", bound},               {"growth_mib", growth},
                          {"samples", nlohmann::json::array()}};
    for (const Sample& s : samples) {
      out["samples"].push_back({{"episodes", s.episodes}, {"seconds", s.seconds}, {"rss_mib", s.rss_mib}});
    }
    std::ofstream(options.json) << out.dump(1) << "\n";
  }
  std::printf("  run kept in %s\n", dir.c_str());
  return summary.completed == options.episodes ? 0 : 1;
}

}  // namespace mtg::cli
