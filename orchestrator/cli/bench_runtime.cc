// `mtg bench runtime`: episodes per second of text-only oracle runs over the bus with 1, 2 and 4
// episodes in flight, and the per-step latency read back from the run's own recording (the
// recorder stamps every message on arrival, one clock for all processes).

#include <lcm/lcm-cpp.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "bus/channels.h"
#include "bus/recording.h"
#include "bus/url.h"
#include "core/tasks/job.h"
#include "core/tasks/task_db.h"
#include "core/util/error.h"
#include "mtg/agent_action_t.hpp"
#include "mtg/observation_t.hpp"
#include "orchestrator/cli/bench_commands.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/run_engine.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::cli {
namespace {

namespace fs = std::filesystem;

// The middle value, or the mean of the two middle ones.
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2.0;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

struct StepLatencies {
  std::vector<double> cycle_ms;    // observation n -> observation n+1 (one whole step)
  std::vector<double> service_ms;  // action n -> observation n+1 (scene-graph service and two hops)
  std::vector<double> agent_ms;    // observation n -> action n (agent and two hops)
};

// Receive times (µs) per (episode, attempt) and step, from every recording of `run_dir`.
StepLatencies step_latencies(const fs::path& run_dir) {
  using Key = std::pair<std::int64_t, std::int32_t>;
  std::map<Key, std::map<int, std::int64_t>> obs, act;
  bus::for_each_recorded_event(run_dir, [&](const lcm::LogEvent& ev) {
    if (bus::is_episode_channel(ev.channel, bus::EpisodeStream::kObservation)) {
      mtg::observation_t m{};
      if (m.decode(ev.data, 0, ev.datalen) >= 0) obs[{m.header.episode_id, m.header.attempt}][m.step] = ev.timestamp;
    } else if (bus::is_episode_channel(ev.channel, bus::EpisodeStream::kAction)) {
      mtg::agent_action_t m{};
      if (m.decode(ev.data, 0, ev.datalen) >= 0) act[{m.header.episode_id, m.header.attempt}][m.step] = ev.timestamp;
    }
  });
  StepLatencies out;
  for (const auto& [key, steps] : obs) {
    const auto& acts = act[key];
    for (const auto& [step, t] : steps) {
      const auto next = steps.find(step + 1);
      if (next == steps.end()) continue;
      out.cycle_ms.push_back(static_cast<double>(next->second - t) / 1000.0);
      const auto a = acts.find(step);
      if (a == acts.end()) continue;
      out.service_ms.push_back(static_cast<double>(next->second - a->second) / 1000.0);
      out.agent_ms.push_back(static_cast<double>(a->second - t) / 1000.0);
    }
  }
  return out;
}

void print_latency(const char* what, const std::vector<double>& ms) {
  std::printf("  %-44s median %6.2f ms   p99 %6.2f ms   (%zu steps)\n", what, percentile(ms, 0.5), percentile(ms, 0.99),
              ms.size());
}

}  // namespace

int run_bench_runtime(const BenchRuntimeOptions& options) {
  const fs::path work = fresh_scratch_folder(options.work, "runtime");

  const auto by_id = bench_task_set(work, options.scene, options.data_dir, options.per_level);
  const std::string tasks_db = (work / "tasks.sqlite").string();

  std::printf("runtime: text-only oracle episodes on %s, %d tasks per level (L1-L3), over %s\n", options.scene.c_str(),
              options.per_level, bus::default_url().c_str());
  // Each round runs every parallelism once; speed-ups compare runs of the same round, so a
  // machine whose speed drifts (a shared VM) skews every parallelism alike.
  std::map<int, std::vector<double>> rates, speedups;
  for (int round = 1; round <= options.rounds; ++round) {
    double one = 0.0;
    for (const int k : options.parallel) {
      orchestrator::RunPlan plan;
      // The folder has the short name; the run id is unique (new_run_id), like `mtg run`'s, so
      // two benches on one bus at once do not take each other's messages.
      const std::string name = "parallel-" + std::to_string(k) + (round > 1 ? "-round-" + std::to_string(round) : "");
      plan.run_id = orchestrator::new_run_id(name);
      plan.tasks_db = tasks_db;
      plan.agents = {"oracle"};
      plan.levels = {1, 2, 3};
      plan.limit = options.per_level;
      plan.parallel = k;
      plan.data_dir = options.data_dir;
      plan.bus_url = bus::normalize_url(bus::default_url());
      plan = orchestrator::make_plan(std::move(plan), by_id);
      const fs::path dir = work / name;
      fs::create_directories(dir);
      orchestrator::save_plan(plan, dir);
      const orchestrator::EngineOptions engine{
          .progress = false, .recorder = "mtg", .vlm_args = {}, .remote = {}, .dataset_json = {}};
      const auto summary = orchestrator::run_plan(plan, dir, by_id, engine);
      long steps = 0, succeeded = 0;
      for (const auto& row : orchestrator::read_results(dir / "results.sqlite")) {
        steps += row.steps;
        succeeded += row.success ? 1 : 0;
      }
      const double eps = static_cast<double>(summary.completed) / summary.episode_seconds;
      if (one == 0.0) one = eps;
      rates[k].push_back(eps);
      speedups[k].push_back(eps / one);
      std::printf("  round %d, parallel %d: %ld episodes (%ld succeeded, %ld steps) in %.2f s = %6.1f episodes/s"
                  "  (%.2fx one; %.2f s with process start and stop)\n",
                  round, k, static_cast<long>(summary.completed), succeeded, steps, summary.episode_seconds, eps,
                  eps / one, summary.seconds);
      if (k == 1 && round == 1) {
        const StepLatencies lat = step_latencies(dir);
        print_latency("per step, observation to next observation", lat.cycle_ms);
        print_latency("  action to next observation (scene graph)", lat.service_ms);
        print_latency("  observation to action (oracle agent)", lat.agent_ms);
      }
    }
  }
  for (const int k : options.parallel) {
    const auto& r = rates[k];
    std::printf("  parallel %d: median %6.1f episodes/s (%.1f-%.1f), median %.2fx one in the same round, over %d"
                " rounds\n",
                k, median(r), *std::min_element(r.begin(), r.end()), *std::max_element(r.begin(), r.end()),
                median(speedups[k]), options.rounds);
  }
  std::printf("  runs kept in %s\n", work.c_str());
  return 0;
}

}  // namespace mtg::cli
