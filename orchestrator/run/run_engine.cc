#include "orchestrator/run/run_engine.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <set>

#include "bus/convert.h"
#include "bus/header.h"
#include "bus/process/stop_signals.h"
#include "core/episode/outcomes.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "orchestrator/remote/lease_launcher.h"
#include "orchestrator/remote/merge_recordings.h"
#include "orchestrator/run/local_runtime.h"
#include "orchestrator/run/progress.h"
#include "orchestrator/run/results_db.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// This process's CPU and that of its children that have ended (the launcher has stopped them).
double cpu_seconds_with_children() {
  double total = 0.0;
  for (const int who : {RUSAGE_SELF, RUSAGE_CHILDREN}) {
    rusage u{};
    if (::getrusage(who, &u) != 0) continue;
    total += static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
             1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  return total;
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

class Engine final : public LaunchSink {
 public:
  Engine(const RunPlan& plan, const fs::path& run_dir, const std::map<std::string, tasks::Task>& tasks,
         Launcher& launcher, RunCounts& counts, const EngineOptions& options)
      : plan_(plan), tasks_(tasks), launcher_(launcher), counts_(counts), options_(options),
        results_(run_dir / "results.sqlite"), stamp_(plan.run_id, "orchestrator:" + std::to_string(::getpid())) {}

  RunSummary run() {
    const auto started = Clock::now();
    const double cpu_at_start = cpu_seconds_with_children();
    RunSummary summary;
    summary.planned = static_cast<std::int64_t>(plan_.episodes.size());
    // One read of what earlier invocations finished: what to skip, and the counts so far. An
    // episode the infrastructure gave up on has no verdict: it runs again (its row is replaced).
    std::set<bus::EpisodeId> finished;
    std::int64_t given_up_before = 0;
    for (const auto& row : results_.rows()) {
      book_cost(row);
      if (row.status != "scored") {
        ++given_up_before;
        continue;
      }
      finished.insert(row.episode_id);
      count(row);
    }
    if (given_up_before > 0) {
      log::info(std::to_string(given_up_before) + " episode(s) given up by the infrastructure before run again");
    }
    summary.already_done = static_cast<std::int64_t>(finished.size());
    for (const auto& e : plan_.episodes) {
      if (finished.count(e.id) == 0) pending_.push_back(e.id);
      by_id_[e.id] = &e;
    }
    counts_.planned = summary.planned;
    if (pending_.empty()) {
      summary.seconds = seconds_since(started);
      return summary;
    }
    // Spent already reaches the cap (a resume with the same --max-cost): start nothing at all.
    if (over_budget()) {
      stop_launching();
      summary.not_started = not_started_;
      summary.budget_stop = budget_line();
      summary.seconds = seconds_since(started);
      return summary;
    }
    // A restarted coordinator finds attempts its workers still run: they stay in flight.
    for (const AdoptedAttempt& a : launcher_.open()) {
      const auto it = std::find(pending_.begin(), pending_.end(), a.episode);
      if (it == pending_.end()) continue;
      pending_.erase(it);
      in_flight_[a.episode] = Flight{a.attempt, 1, Clock::now()};
    }
    Progress progress(summary.planned, summary.already_done, options_.progress);
    progress_ = &progress;
    const auto episodes_started = Clock::now();
    process::install_stop_signals();

    while (!pending_.empty() || !waiting_retries_.empty() || !in_flight_.empty()) {
      if (process::stop_signal_received()) {
        summary.interrupted = true;
        break;
      }
      dispatch();
      counts_.in_flight = static_cast<int>(in_flight_.size());
      launcher_.poll(20, *this);
    }
    summary.episode_seconds = seconds_since(episodes_started);
    progress.draw(true);
    if (options_.hold_after_last && !summary.interrupted && pending_.empty() && in_flight_.empty()) {
      std::fprintf(stderr, "\nevery episode is played: the page shows the last verdict and your score until you stop "
                           "(Ctrl-C)\n");
      while (!process::stop_signal_received()) launcher_.poll(100, *this);
    }
    counts_.in_flight = 0;
    launcher_.close();
    process::restore_default_signals();
    summary.completed = completed_;
    summary.errors = errors_;
    summary.retries = retries_;
    summary.restarts = launcher_.restarts();
    summary.stopped_agents = stopped_agents_;
    summary.not_run = not_run_;
    summary.not_started = not_started_;
    if (budget_stopped_) summary.budget_stop = budget_line();
    summary.seconds = seconds_since(started);
    summary.cpu_seconds = cpu_seconds_with_children() - cpu_at_start;
    return summary;
  }

  void on_result(const mtg::episode_result_t& m, const std::string& worker,
                 const bus::RecordingRef* recording) override {
    const auto it = in_flight_.find(bus::episode_of(m.header));
    if (it == in_flight_.end() || it->second.attempt != m.header.attempt) return;  // stale or duplicate
    // Neither a lost message nor a failing API is the agent's failure: try the episode again.
    const auto cause = episode::cause_from_string(m.cause);
    if (!cause || !episode::stage_from_string(m.stage)) {  // a judge from another version: never score it
      spent_usd_ += m.spent_usd;  // paid all the same, and no row keeps it
      retry(bus::episode_of(m.header), "result with unknown stage '" + m.stage + "' or cause '" + m.cause + "'");
      return;
    }
    if (episode::is_retried(*cause)) {
      spent_usd_ += m.spent_usd;
      retry(bus::episode_of(m.header), m.detail,
            cause == episode::Cause::kProviderError ? episode::Cause::kProviderError : episode::Cause::kInfrastructure);
      return;
    }
    EpisodeRow row = base_row(bus::episode_of(m.header), m.header.attempt);
    set_verdict(row, m);
    row.usage = bus::episode_usage(m);
    row.worker = worker;
    row.wall_ms = 1000.0 * seconds_since(it->second.started);
    in_flight_.erase(it);
    store(row, true, recording);
  }

  void on_failure(bus::EpisodeId episode_id, int attempt, const std::string& why) override {
    const auto it = in_flight_.find(episode_id);
    if (it != in_flight_.end() && it->second.attempt == attempt) retry(episode_id, why);
  }

  void on_agent_stopped(const std::string& spec, const std::string& why) override {
    if (!stopped_agents_.emplace(spec, why).second) return;
    log::error("agent " + spec + " stopped: " + why);
    const auto theirs_id = [&](bus::EpisodeId id) { return by_id_.at(id)->agent == spec; };
    not_run_ += static_cast<std::int64_t>(std::erase_if(pending_, theirs_id));
    not_run_ += static_cast<std::int64_t>(
        std::erase_if(waiting_retries_, [&](const Retry& retry) { return theirs_id(retry.episode); }));
    for (auto it = in_flight_.begin(); it != in_flight_.end();) {
      const bool theirs = by_id_.at(it->first)->agent == spec;
      if (theirs) {
        ++not_run_;
        launcher_.drop(it->first, it->second.attempt);
      }
      it = theirs ? in_flight_.erase(it) : std::next(it);
    }
  }

 private:
  struct Flight {
    int attempt = 0;
    int tries = 1;  // attempts of this episode made by this invocation, this one included
    Clock::time_point started;
  };
  struct Retry {
    bus::EpisodeId episode;
    int attempt = 0;
    int tries = 1;
  };

  void dispatch() {
    while (!waiting_retries_.empty() || !pending_.empty()) {
      // Before the slots: a budget reached while every slot is busy still stops what waits.
      if (over_budget()) {
        stop_launching();
        break;
      }
      if (launcher_.free_slots() <= 0 || (plan_.parallel > 0 && static_cast<int>(in_flight_.size()) >= plan_.parallel)) {
        break;
      }
      // Retries first, oldest first: they have waited longest.
      if (!waiting_retries_.empty()) {
        const Retry r = waiting_retries_.front();
        waiting_retries_.pop_front();
        send_start(r.episode, r.attempt, r.tries);
      } else {
        const bus::EpisodeId id = pending_.front();
        pending_.pop_front();
        send_start(id, launcher_.next_attempt(id), 1);
      }
    }
    const bool stuck = in_flight_.empty() && (!waiting_retries_.empty() || !pending_.empty());
    if (stuck && !said_stuck_) {
      log::warn(std::to_string(waiting_retries_.size() + pending_.size()) +
                " episode(s) wait for a free slot and none is in flight (all workers lost?); waiting for one");
    }
    said_stuck_ = stuck;
  }

  void send_start(bus::EpisodeId id, int attempt, int tries) {
    const PlannedEpisode& e = *by_id_.at(id);
    const auto task = tasks_.find(e.task_id);
    if (task == tasks_.end()) throw Error("task " + e.task_id + " of the plan is not in " + plan_.tasks_db);
    EpisodeLaunch launch;
    launch.truth = bus::truth_message(task->second);
    launch.truth.header = stamp_.next(id, attempt, "truth");
    mtg::episode_start_t& m = launch.start;
    m.header = stamp_.next(id, attempt, "start");
    m.task = bus::to_message(task->second);
    m.agent = e.agent;
    m.seed = static_cast<std::int64_t>(e.seed);
    m.step_limit = std::max(plan_.step_limit, task->second.step_limit);
    m.render = plan_.render;
    m.data_dir = plan_.data_dir;
    m.object_names = plan_.object_names;
    m.lookalike_aid = bus::to_message(plan_.lookalike_aid);
    m.numbering = bus::to_message(plan_.numbering);
    in_flight_[id] = Flight{attempt, tries, Clock::now()};
    launcher_.launch(launch);
  }

  void retry(bus::EpisodeId id, const std::string& why, episode::Cause cause = episode::Cause::kInfrastructure) {
    const auto it = in_flight_.find(id);
    if (it == in_flight_.end()) return;
    const Flight failed = it->second;
    in_flight_.erase(it);
    if (failed.tries >= plan_.max_attempts) {
      log::warn("episode " + to_string(id) + " given up after " + std::to_string(failed.tries) + " attempts: " + why);
      EpisodeRow row = base_row(id, failed.attempt);
      row.status = "error";
      row.stage = episode::to_string(episode::Stage::kStart);
      row.cause = episode::to_string(cause);
      row.detail = why;
      store(row, false);
      ++errors_;
      return;
    }
    const int attempt = failed.attempt + 1;
    log::info("episode " + to_string(id) + ": retrying (attempt " + std::to_string(attempt) + "): " + why);
    ++retries_;
    if (progress_ != nullptr) progress_->retry();
    // Sent by dispatch() when a slot is free: a lost host may have taken its slots with it.
    waiting_retries_.push_back(Retry{id, attempt, failed.tries + 1});
  }

  EpisodeRow base_row(bus::EpisodeId id, int attempt) const {
    const PlannedEpisode& e = *by_id_.at(id);
    const tasks::Task& t = tasks_.at(e.task_id);
    EpisodeRow row;
    row.episode_id = id;
    row.task_id = e.task_id;
    row.scene = t.scene;
    row.level = t.level;
    row.task_type = t.type;
    row.agent = e.agent;
    row.attempt = attempt;
    row.subtask_ip = "[]";
    return row;
  }

  void store(const EpisodeRow& row, bool scored, const bus::RecordingRef* recording = nullptr) {
    stamp_.forget_episode(row.episode_id);  // stored: no more starts of it from this invocation
    if (results_.insert(row, recording)) {
      ++completed_;
      book_cost(row);
      if (options_.stored != nullptr) options_.stored->fetch_add(1, std::memory_order_relaxed);
      count(row);
      if (progress_ != nullptr) {
        progress_->record(row.agent, row.success, row.ip, scored);
        progress_->draw();
      }
    }
  }

  void count(const EpisodeRow& row) {
    ++counts_.finished;
    if (row.status != "scored") {
      ++counts_.errors;
      return;
    }
    ++counts_.scored;
    counts_.successes += row.success ? 1 : 0;
    counts_.ip_sum += row.ip;
  }

  // The budget's books (Budget, run_engine.h).
  void book_cost(const EpisodeRow& row) {
    spent_usd_ += row.usage.spent_usd;
    if (row.status != "scored") return;
    AgentCost& c = agent_cost_[row.agent];
    ++c.episodes;
    c.spent_usd += row.usage.spent_usd;
  }

  // What an episode of `agent` in flight is expected to cost: what the run's episodes of that
  // agent have cost on average, or the estimate's figure until one has finished.
  double expected_cost(const std::string& agent) const {
    if (const auto it = agent_cost_.find(agent); it != agent_cost_.end() && it->second.episodes > 0) {
      return it->second.spent_usd / static_cast<double>(it->second.episodes);
    }
    const auto& estimate = options_.budget.expected_episode_cost_usd;
    const auto it = estimate.find(agent);
    return it == estimate.end() ? 0.0 : it->second;
  }

  double in_flight_cost() const {
    double total = 0.0;
    for (const auto& [id, flight] : in_flight_) total += expected_cost(by_id_.at(id)->agent);
    return total;
  }

  bool over_budget() const {
    if (budget_stopped_) return true;
    const double cap = options_.budget.max_cost_usd;
    return cap > 0.0 && spent_usd_ + in_flight_cost() >= cap;
  }

  // No more starts: what waits stays unfinished (no row), for a resume with a higher cap. Called
  // again for retries that fail later.
  void stop_launching() {
    if (!budget_stopped_) {
      budget_stopped_ = true;
      stop_spent_usd_ = spent_usd_;
      stop_in_flight_usd_ = in_flight_cost();
      log::info("budget reached: no new episodes" +
                (in_flight_.empty() ? std::string() : "; waiting for the " + std::to_string(in_flight_.size()) + " in flight"));
    }
    not_started_ += static_cast<std::int64_t>(pending_.size() + waiting_retries_.size());
    pending_.clear();
    waiting_retries_.clear();
  }

  std::string budget_line() const {
    auto usd = [](double x) {
      char buf[48];
      std::snprintf(buf, sizeof buf, x >= 1.0 || x == 0.0 ? "$%.2f" : "$%.4f", x);
      return std::string(buf);
    };
    return "budget: " + usd(stop_spent_usd_) + " spent + " + usd(stop_in_flight_usd_) + " in flight reached --max-cost " +
           usd(options_.budget.max_cost_usd) + "; " + std::to_string(not_started_) +
           " episode(s) not started; run the same command again with a higher --max-cost to go on";
  }

  const RunPlan& plan_;
  const std::map<std::string, tasks::Task>& tasks_;
  Launcher& launcher_;
  RunCounts& counts_;
  EngineOptions options_;
  ResultsDb results_;
  bus::HeaderStamper stamp_;
  std::map<bus::EpisodeId, const PlannedEpisode*> by_id_;
  std::deque<bus::EpisodeId> pending_;
  std::deque<Retry> waiting_retries_;  // sent before pending_
  bool said_stuck_ = false;
  std::map<bus::EpisodeId, Flight> in_flight_;
  Progress* progress_ = nullptr;
  std::int64_t completed_ = 0, errors_ = 0, retries_ = 0, not_run_ = 0;
  std::map<std::string, std::string> stopped_agents_;
  struct AgentCost {
    std::int64_t episodes = 0;  // scored, every invocation
    double spent_usd = 0.0;
  };
  std::map<std::string, AgentCost> agent_cost_;
  double spent_usd_ = 0.0;  // the run's, every invocation, retried attempts of this one included
  bool budget_stopped_ = false;
  double stop_spent_usd_ = 0.0, stop_in_flight_usd_ = 0.0;  // when the cap was reached
  std::int64_t not_started_ = 0;
};

}  // namespace

RuntimeConfig runtime_config(const RunPlan& plan, const EngineOptions& options) {
  RuntimeConfig c;
  c.run_id = plan.run_id;
  c.bus_url = plan.bus_url;
  c.profile = plan.profile;
  c.platform_rules = plan.platform_rules;
  c.render = plan.render;
  c.renderers = options.renderers;
  c.image_width = plan.image_width;
  c.image_height = plan.image_height;
  c.image_encoding = plan.image_encoding;
  c.agents = plan.agents;
  c.vlm_args = options.vlm_args;
  c.parallel = plan.parallel;
  c.episode_timeout_s = plan.episode_timeout_s;
  c.recorder = options.recorder;
  c.dataset_json = options.dataset_json;
  c.allow_data_mismatch = plan.allow_data_mismatch;
  c.data_dir = plan.data_dir;
  c.play_host = options.play_host;
  c.play_port = options.play_port;
  c.play_socket = options.play_socket;
  c.attempts_per_invocation = plan.max_attempts;
  return c;
}

RunSummary run_plan(const RunPlan& plan, const fs::path& run_dir, const std::map<std::string, tasks::Task>& tasks,
                    const EngineOptions& options) {
  if (plan.remote) {
    RunCounts counts;  // the launcher announces them to the workers
    remote::LeaseLauncher launcher(runtime_config(plan, options), run_dir, counts, options.remote);
    Engine engine(plan, run_dir, tasks, launcher, counts, options);
    const RunSummary summary = engine.run();
    // Recordings that stayed where they were made are read where they are (bus::recording_files):
    // gathering them here is the traffic they were kept away from.
    if (options.remote.recordings.kind == remote::RecordingsPlace::Kind::kCoordinator) remote::merge_recordings(run_dir);
    return summary;
  }
  LocalRuntime launcher(runtime_config(plan, options), run_dir);
  return run_plan_with(plan, run_dir, tasks, launcher, options);
}

RunSummary run_plan_with(const RunPlan& plan, const fs::path& run_dir, const std::map<std::string, tasks::Task>& tasks,
                         Launcher& launcher, const EngineOptions& options) {
  RunCounts counts;
  Engine engine(plan, run_dir, tasks, launcher, counts, options);
  return engine.run();
}

}  // namespace mtg::orchestrator
