#include "orchestrator/run/run_engine.h"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <deque>
#include <set>
#include <thread>

#include "agents/builtin/policies.h"
#include "agents/vlm/model_spec.h"
#include "bus/bus.h"
#include "bus/channels.h"
#include "bus/convert.h"
#include "bus/header.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/error_event_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/state_update_t.hpp"
#include "orchestrator/run/progress.h"
#include "orchestrator/run/results_db.h"
#include "orchestrator/run/supervisor.h"

namespace mtg::orchestrator {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

volatile sig_atomic_t g_interrupted = 0;
void on_interrupt(int) { g_interrupted = 1; }

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

class Engine {
 public:
  Engine(const RunPlan& plan, const fs::path& run_dir, const std::map<std::string, tasks::Task>& tasks,
         const EngineOptions& options)
      : plan_(plan), dir_(run_dir), tasks_(tasks), options_(options), results_(run_dir / "results.sqlite"),
        bus_(plan.bus_url), stamp_(plan.run_id, "orchestrator:" + std::to_string(::getpid())),
        supervisor_(run_dir / "logs") {}

  RunSummary run() {
    const auto started = Clock::now();
    RunSummary summary;
    summary.planned = static_cast<std::int64_t>(plan_.episodes.size());
    const std::set<std::int64_t> finished = results_.finished();
    summary.already_done = static_cast<std::int64_t>(finished.size());
    for (const auto& e : plan_.episodes) {
      if (finished.count(e.id) == 0) pending_.push_back(e.id);
      by_id_[e.id] = &e;
    }
    if (pending_.empty()) {
      summary.seconds = seconds_since(started);
      return summary;
    }
    subscribe();
    start_processes();
    Progress progress(summary.planned, summary.already_done, options_.progress);
    progress_ = &progress;
    const auto episodes_started = Clock::now();
    signal(SIGINT, on_interrupt);
    signal(SIGTERM, on_interrupt);

    while (!pending_.empty() || !in_flight_.empty()) {
      if (g_interrupted) {
        summary.interrupted = true;
        break;
      }
      handle_deaths();
      dispatch();
      bus_.handle_once(20);
      check_timeouts();
    }
    summary.episode_seconds = seconds_since(episodes_started);
    progress.draw(true);
    shutdown();
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    summary.completed = completed_;
    summary.errors = errors_;
    summary.retries = retries_;
    summary.restarts = supervisor_.restarts();
    summary.stopped_agents = stopped_agents_;
    summary.not_run = not_run_;
    summary.seconds = seconds_since(started);
    return summary;
  }

 private:
  struct Flight {
    int attempt = 0;
    Clock::time_point started, last_activity;
  };

  void subscribe() {
    bus_.subscribe<mtg::episode_result_t>(bus::kEpisodeResult, [this](const std::string&, const mtg::episode_result_t& m) {
      if (m.header.run_id == plan_.run_id) on_result(m);
    });
    bus_.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [this](const std::string&, const mtg::heartbeat_t& m) {
      ready_pids_.insert(m.pid);
    });
    // Liveness for the episode time-out: one state update per step suffices, and every stream
    // subscribed to costs this process a wake-up per message.
    bus_.subscribe<mtg::state_update_t>(bus::episode_channel_regex(bus::EpisodeStream::kState),
                                        [this](const std::string&, const mtg::state_update_t& m) { touch(m.header); });
    bus_.subscribe<mtg::error_event_t>(bus::kError, [this](const std::string&, const mtg::error_event_t& m) {
      if (m.header.run_id != plan_.run_id) return;
      if (m.severity == "fatal" && m.source.rfind("agent:", 0) == 0) {
        stop_agent(m.source.substr(6), m.message);
        return;
      }
      log::warn("error from " + m.source + ": " + m.message);
      const auto it = in_flight_.find(m.header.episode_id);
      if (it != in_flight_.end() && it->second.attempt == m.header.attempt) retry(m.header.episode_id, m.message);
    });
  }

  void start_processes() {
    const fs::path bin = executable_dir();
    // The recording first, so it sees every message of the run; one file per invocation.
    int k = 0;
    while (fs::exists(dir_ / ("bus-" + std::to_string(k) + ".lcmlog"))) ++k;
    const fs::path log = dir_ / ("bus-" + std::to_string(k) + ".lcmlog");
    // Both append, so a restarted recorder continues the file.
    if (options_.recorder == "lcm-logger") {
      supervisor_.start("recorder", {"/usr/bin/lcm-logger", "--lcm-url=" + plan_.bus_url, "--append", log.string()});
    } else if (options_.recorder == "mtg") {
      supervisor_.start("recorder", {(bin / "mtg_recorder").string(), "--url", plan_.bus_url, log.string()});
    } else {
      throw Error("unknown recorder '" + options_.recorder + "' (mtg or lcm-logger)");
    }
    if (recorder_beats()) {
      wait_ready({"recorder"}, 60.0);  // subscribed before its first heartbeat
    } else {
      for (int i = 0; i < 200 && !fs::exists(log); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (!fs::exists(log)) throw Error("lcm-logger did not start (see " + (dir_ / "logs/recorder.log").string() + ")");
    }

    const std::vector<std::string> common = {"--url", plan_.bus_url, "--run", plan_.run_id};
    auto with = [&](std::vector<std::string> argv) {
      argv.insert(argv.end(), common.begin(), common.end());
      return argv;
    };
    supervisor_.start("scene_graph", with({(bin / "mtg_scene_graph").string(), "--profile", plan_.profile,
                                           "--image-width", std::to_string(plan_.image_width), "--image-height",
                                           std::to_string(plan_.image_height), "--image-encoding",
                                           plan_.image_encoding}));
    if (plan_.render) {
      supervisor_.start("renderer", with({(bin / "mtg_renderer").string(), "--profile", plan_.profile}));
      names_.push_back("renderer");
    }
    supervisor_.start("judge", with({(bin / "mtg_judge").string(), "--profile", plan_.profile}));
    names_.push_back("scene_graph");
    names_.push_back("judge");
    bool model_agents = false;
    for (std::size_t i = 0; i < plan_.agents.size(); ++i) {
      const std::string& spec = plan_.agents[i];
      const std::string name = "agent-" + std::to_string(i);
      if (agents::is_builtin_agent(spec)) {
        supervisor_.start(name, with({(bin / "mtg_agent").string(), "--agent", spec}));
      } else if (vlm::is_model_spec(spec)) {
        // As many calls in flight as episodes, unless the settings say otherwise.
        std::vector<std::string> argv = {(bin / "mtg_vlm_agent").string(), "--agent", spec, "--workers",
                                         std::to_string(plan_.parallel)};
        argv.insert(argv.end(), options_.vlm_args.begin(), options_.vlm_args.end());
        supervisor_.start(name, with(argv));
        model_agents = true;
      } else {
        throw Error("unknown agent '" + spec + "' (oracle, random, replay:<run>, script:<file>, openai:<model>, "
                    "anthropic:<model>, gemini:<model>, openai-compatible:<url>:<model>)");
      }
      agent_process_[spec] = name;
      names_.push_back(name);
    }
    if (model_agents) {
      supervisor_.start("governor", with({(bin / "mtg_governor").string()}));
      names_.push_back("governor");
    }
    wait_ready(names_, 60.0);
  }

  bool recorder_beats() const { return options_.recorder != "lcm-logger"; }

  void wait_ready(const std::vector<std::string>& names, double timeout_s) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (Clock::now() < deadline) {
      bool all = true;
      for (const auto& n : names) all = all && ready_pids_.count(supervisor_.pid(n)) != 0;
      if (all) return;
      bus_.handle_once(50);
      for (const auto& died : supervisor_.poll()) log::warn(died + " died while starting");
    }
    std::string missing;
    for (const auto& n : names) {
      if (ready_pids_.count(supervisor_.pid(n)) == 0) missing += " " + n;
    }
    throw Error("processes not ready after " + std::to_string(static_cast<int>(timeout_s)) + " s:" + missing +
                " (their logs are in " + (dir_ / "logs").string() + ")");
  }

  void handle_deaths() {
    const auto died = supervisor_.poll();
    if (died.empty()) return;
    std::set<std::string> affected_agents;
    bool all = false;
    for (const auto& name : died) {
      // The governor holds no episode: its restart only delays calls.
      if (name == "scene_graph" || name == "judge" || name == "recorder" || name == "renderer") all = true;
      for (const auto& [spec, process] : agent_process_) {
        if (process == name) affected_agents.insert(spec);
      }
    }
    std::vector<std::int64_t> retry_ids;
    for (const auto& [id, f] : in_flight_) {
      if (all || affected_agents.count(by_id_.at(id)->agent)) retry_ids.push_back(id);
    }
    std::vector<std::string> restarted;
    for (const auto& name : died) {
      if (name != "recorder" || recorder_beats()) restarted.push_back(name);  // lcm-logger sends no heartbeat
    }
    wait_ready(restarted, 60.0);
    for (const auto id : retry_ids) retry(id, "a process it depended on was restarted");
  }

  void dispatch() {
    while (static_cast<int>(in_flight_.size()) < plan_.parallel && !pending_.empty()) {
      const std::int64_t id = pending_.front();
      pending_.pop_front();
      send_start(id, 0);  // retries do not queue: retry() sends the next attempt itself
    }
  }

  void send_start(std::int64_t id, int attempt) {
    const PlannedEpisode& e = *by_id_.at(id);
    const auto task = tasks_.find(e.task_id);
    if (task == tasks_.end()) throw Error("task " + e.task_id + " of the plan is not in " + plan_.tasks_db);
    mtg::episode_start_t m{};
    m.header = stamp_.next(id, attempt, "start");
    m.task = bus::to_message(task->second);
    m.agent = e.agent;
    m.seed = static_cast<std::int64_t>(e.seed);
    m.step_limit = std::max(plan_.step_limit, task->second.step_limit);
    m.render = plan_.render;
    m.data_dir = plan_.data_dir;
    Flight f;
    f.attempt = attempt;
    f.started = f.last_activity = Clock::now();
    in_flight_[id] = f;
    bus_.publish(bus::kEpisodeStart, m);
  }

  void touch(const mtg::header_t& h) {
    if (h.run_id != plan_.run_id) return;
    const auto it = in_flight_.find(h.episode_id);
    if (it != in_flight_.end() && it->second.attempt == h.attempt) it->second.last_activity = Clock::now();
  }

  void check_timeouts() {
    std::vector<std::int64_t> stuck;
    for (const auto& [id, f] : in_flight_) {
      if (seconds_since(f.last_activity) > plan_.episode_timeout_s) stuck.push_back(id);
    }
    for (const auto id : stuck) {
      retry(id, "no message for " + std::to_string(static_cast<int>(plan_.episode_timeout_s)) + " s");
    }
  }

  void stop_agent(const std::string& spec, const std::string& why) {
    if (!stopped_agents_.emplace(spec, why).second) return;
    log::error("agent " + spec + " stopped: " + why);
    std::deque<std::int64_t> keep;
    for (const auto id : pending_) {
      if (by_id_.at(id)->agent == spec) {
        ++not_run_;
      } else {
        keep.push_back(id);
      }
    }
    pending_.swap(keep);
    for (auto it = in_flight_.begin(); it != in_flight_.end();) {
      const bool theirs = by_id_.at(it->first)->agent == spec;
      not_run_ += theirs ? 1 : 0;
      it = theirs ? in_flight_.erase(it) : std::next(it);
    }
  }

  void retry(std::int64_t id, const std::string& why, const std::string& cause = "infrastructure") {
    const auto it = in_flight_.find(id);
    if (it == in_flight_.end()) return;
    const int attempt = it->second.attempt + 1;
    in_flight_.erase(it);
    if (attempt >= plan_.max_attempts) {
      log::warn("episode " + std::to_string(id) + " given up after " + std::to_string(attempt) + " attempts: " + why);
      EpisodeRow row = base_row(id, attempt - 1);
      row.status = "error";
      row.stage = "start";
      row.cause = cause;
      row.detail = why;
      store(row, false);
      ++errors_;
      return;
    }
    log::info("episode " + std::to_string(id) + ": retrying (attempt " + std::to_string(attempt) + "): " + why);
    ++retries_;
    if (progress_ != nullptr) progress_->retry();
    send_start(id, attempt);
  }

  EpisodeRow base_row(std::int64_t id, int attempt) const {
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

  void on_result(const mtg::episode_result_t& m) {
    const auto it = in_flight_.find(m.header.episode_id);
    if (it == in_flight_.end() || it->second.attempt != m.header.attempt) return;  // stale or duplicate
    // Neither a lost message nor a failing API is the agent's failure: try the episode again.
    if (m.cause == "transport_error" || m.cause == "provider_error") {
      retry(m.header.episode_id, m.detail, m.cause == "provider_error" ? "provider_error" : "infrastructure");
      return;
    }
    EpisodeRow row = base_row(m.header.episode_id, m.header.attempt);
    set_verdict(row, m);
    set_usage(row, m);
    row.wall_ms = 1000.0 * seconds_since(it->second.started);
    in_flight_.erase(it);
    store(row, true);
  }

  void store(const EpisodeRow& row, bool scored) {
    if (results_.insert(row)) {
      ++completed_;
      if (progress_ != nullptr) {
        progress_->record(row.success, row.ip, scored);
        progress_->draw();
      }
    }
  }

  void shutdown() {
    mtg::run_control_t stop{};
    stop.header = stamp_.next(-1, 0, "control");
    stop.command = "shutdown";
    bus_.publish(bus::kControl, stop);
    for (const auto& name : names_) supervisor_.stop(name, SIGTERM, 3000);
    supervisor_.stop("recorder", SIGINT, 3000);  // it records what is queued, then closes
  }

  const RunPlan& plan_;
  fs::path dir_;
  const std::map<std::string, tasks::Task>& tasks_;
  EngineOptions options_;
  ResultsDb results_;
  bus::Bus bus_;
  bus::HeaderStamper stamp_;
  Supervisor supervisor_;
  std::vector<std::string> names_;
  std::map<std::string, std::string> agent_process_;
  std::set<int> ready_pids_;
  std::map<std::int64_t, const PlannedEpisode*> by_id_;
  std::deque<std::int64_t> pending_;
  std::map<std::int64_t, Flight> in_flight_;
  Progress* progress_ = nullptr;
  std::int64_t completed_ = 0, errors_ = 0, retries_ = 0, not_run_ = 0;
  std::map<std::string, std::string> stopped_agents_;
};

}  // namespace

RunSummary run_plan(const RunPlan& plan, const fs::path& run_dir, const std::map<std::string, tasks::Task>& tasks,
                    const EngineOptions& options) {
  Engine engine(plan, run_dir, tasks, options);
  return engine.run();
}

}  // namespace mtg::orchestrator
