#include "orchestrator/run/local_runtime.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "agents/builtin/policies.h"
#include "agents/human/page_guard.h"
#include "agents/vlm/model_spec.h"
#include "bus/channels.h"
#include "bus/error_events.h"
#include "bus/process/subprocess.h"
#include "core/render/render_pool.h"
#include "core/util/error.h"
#include "core/util/log.h"
#include "core/util/parallel.h"
#include "mtg/error_event_t.hpp"
#include "mtg/heartbeat_t.hpp"
#include "mtg/recorded_t.hpp"
#include "mtg/run_control_t.hpp"
#include "mtg/state_update_t.hpp"
#include "orchestrator/run/hang_rule.h"
#include "orchestrator/run/process_memory.h"

namespace mtg::orchestrator {

namespace fs = std::filesystem;

namespace {

// The last line that is not empty ("no message" when there is none).
std::string last_line(std::istream& in) {
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) last = line;
  }
  return last.empty() ? "no message" : last;
}

// The last line a process wrote to its log: usually why it stopped.
std::string last_line_of(const fs::path& log) {
  std::ifstream in(log);
  return last_line(in);
}

// Hardware GPUs the renderer finds (its EGL probe; GL stays out of this process). 0 when the
// probe fails: the pool is then sized for llvmpipe, which still draws.
int count_gpus(const fs::path& bin) {
  try {
    const process::CommandOutput out = process::run_command({(bin / "mtg_renderer").string(), "--count-gpus"});
    // The count is the last line: EGL drivers may warn on stderr before it.
    std::istringstream lines(out.output);
    if (out.exit_code == 0) return std::max(0, std::stoi(last_line(lines)));
    log::warn("mtg_renderer --count-gpus failed: " + out.output);
  } catch (const std::exception& e) {
    log::warn(std::string("mtg_renderer --count-gpus: ") + e.what());
  }
  return 0;
}

}  // namespace

LocalRuntime::LocalRuntime(RuntimeConfig config, fs::path dir)
    : config_(std::move(config)), dir_(std::move(dir)), bus_(config_.bus_url, config_.network),
      stamp_(config_.run_id, "orchestrator:" + std::to_string(::getpid())), supervisor_(dir_ / "logs", config_.network) {
  subscribe();
}

void LocalRuntime::subscribe() {
  // With a recorder that acknowledges, an attempt is done when both its result (from the judge)
  // and the recorder's acknowledgement are here, in either order: they come from two senders,
  // and the bus does not keep order across senders (the acknowledgement overtook the result in
  // about one run in ten of `mtg bench runtime`, and the attempt then waited out its time-out).
  bus_.subscribe<mtg::episode_result_t>(bus::kEpisodeResult, [this](const std::string&, const mtg::episode_result_t& m) {
    if (m.header.run_id != config_.run_id || sink_ == nullptr) return;
    const auto it = in_flight_.find(bus::episode_of(m.header));
    if (it == in_flight_.end() || it->second.attempt != m.header.attempt) return;  // stale or duplicate
    if (!it->second.result) it->second.result = m;
    if (!recorder_acks() || it->second.recorded) finish(it);
  });
  bus_.subscribe<mtg::recorded_t>(bus::kRecorded, [this](const std::string&, const mtg::recorded_t& m) {
    if (m.header.run_id != config_.run_id || sink_ == nullptr) return;
    recorder_deaths_since_ack_ = 0;
    const auto it = in_flight_.find(bus::episode_of(m.header));
    if (it == in_flight_.end() || it->second.attempt != m.header.attempt) return;
    it->second.recorded = true;
    if (it->second.result) finish(it);
  });
  bus_.subscribe<mtg::heartbeat_t>(bus::kHeartbeat, [this](const std::string&, const mtg::heartbeat_t& m) {
    last_beat_[m.pid] = Clock::now();
  });
  // Liveness for the episode time-out: one state update per step suffices, and every stream
  // subscribed to costs this process a wake-up per message.
  bus_.subscribe<mtg::state_update_t>(bus::episode_channel(bus::EpisodeStream::kState),
                                      [this](const std::string&, const mtg::state_update_t& m) { touch(m.header); });
  bus_.subscribe<mtg::error_event_t>(bus::kError, [this](const std::string&, const mtg::error_event_t& m) {
    if (m.header.run_id != config_.run_id || sink_ == nullptr) return;
    if (const auto agent = bus::stopped_agent(m)) {
      for (auto it = in_flight_.begin(); it != in_flight_.end();) {
        it = it->second.agent == *agent ? in_flight_.erase(it) : std::next(it);
      }
      sink_->on_agent_stopped(*agent, m.message);
      return;
    }
    log::warn("error from " + m.source + ": " + m.message);
    const auto it = in_flight_.find(bus::episode_of(m.header));
    if (it != in_flight_.end() && it->second.attempt == m.header.attempt) fail(bus::episode_of(m.header), m.message, *sink_);
  });
}

std::vector<AdoptedAttempt> LocalRuntime::open() {
  const fs::path bin = executable_dir();
  fs::create_directories(dir_);
  // Answers travel sealed; only the judge, the scene-graph service and the oracle get the key.
  const bus::TruthSeal fresh =
      config_.truth_secret_file.empty()
          ? bus::TruthSeal::random()
          : bus::TruthSeal::derived(bus::Authenticator::read_secret(config_.truth_secret_file), config_.run_id);
  bus_.seal_truths(std::make_shared<const bus::TruthSeal>(bus::TruthSeal::for_run_folder(dir_, fresh)));
  const std::string truth_key = (dir_ / bus::TruthSeal::kFileName).string();
  // The recording first, so it sees every message of the run; one file per invocation.
  int k = 0;
  while (fs::exists(dir_ / ("bus-" + std::to_string(k) + ".lcmlog"))) ++k;
  const fs::path log = dir_ / ("bus-" + std::to_string(k) + ".lcmlog");
  first_attempt_ = k * std::max(1, config_.attempts_per_invocation);
  // Both append, so a restarted recorder continues the file.
  if (config_.recorder == "lcm-logger") {
    supervisor_.start("recorder", {"/usr/bin/lcm-logger", "--lcm-url=" + config_.bus_url, "--append", log.string()});
  } else if (config_.recorder == "mtg") {
    supervisor_.start("recorder", {(bin / "mtg_recorder").string(), "--url", config_.bus_url, "--run", config_.run_id,
                                   log.string()});
  } else {
    throw Error("unknown recorder '" + config_.recorder + "' (mtg or lcm-logger)");
  }
  open_ = true;
  if (recorder_beats()) {
    wait_ready({"recorder"}, 60.0);  // subscribed before its first heartbeat
  } else {
    for (int i = 0; i < 200 && !fs::exists(log); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!fs::exists(log)) throw Error("lcm-logger did not start (see " + (dir_ / "logs/recorder.log").string() + ")");
  }

  const std::vector<std::string> common = {"--url", config_.bus_url, "--run", config_.run_id};
  auto with = [&](std::vector<std::string> argv) {
    argv.insert(argv.end(), common.begin(), common.end());
    return argv;
  };
  const std::vector<render::RendererSlot> renderers =
      config_.render ? render::plan_render_pool(config_.renderers, default_jobs(), count_gpus(bin))
                     : std::vector<render::RendererSlot>{};
  const std::string rules = graph::to_string(config_.platform_rules);
  supervisor_.start("scene_graph", with({(bin / "mtg_scene_graph").string(), "--truth-key-file", truth_key,
                                         "--profile", config_.profile, "--platform-rules", rules,
                                         "--image-width", std::to_string(config_.image_width), "--image-height",
                                         std::to_string(config_.image_height), "--image-encoding",
                                         config_.image_encoding, "--renderers",
                                         std::to_string(std::max<std::size_t>(1, renderers.size()))}));
  for (const render::RendererSlot& slot : renderers) {
    std::vector<std::string> argv = {(bin / "mtg_renderer").string(), "--profile", config_.profile,
                                     "--platform-rules", rules, "--pool-index",
                                     std::to_string(slot.index), "--encode-jobs", std::to_string(slot.encode_threads)};
    if (slot.gpu >= 0) argv.insert(argv.end(), {"--gpu", std::to_string(slot.gpu)});
    if (slot.draw_threads > 0) argv.insert(argv.end(), {"--draw-threads", std::to_string(slot.draw_threads)});
    const std::string name = bus::renderer_role(slot.index);
    supervisor_.start(name, with(argv));
    names_.push_back(name);
  }
  if (!renderers.empty()) {
    log::info(std::to_string(renderers.size()) + " renderer(s), " +
              (renderers.front().gpu >= 0 ? "on the GPU(s)" : "on llvmpipe") + ", " +
              std::to_string(renderers.front().encode_threads) + " encoder thread(s) each");
  }
  supervisor_.start("judge", with({(bin / "mtg_judge").string(), "--truth-key-file", truth_key, "--profile",
                                   config_.profile, "--platform-rules", rules}));
  names_.push_back("scene_graph");
  names_.push_back("judge");
  bool model_agents = false;
  for (std::size_t i = 0; i < config_.agents.size(); ++i) {
    const std::string& spec = config_.agents[i];
    const std::string name = "agent-" + std::to_string(i);
    if (agents::is_builtin_agent(spec)) {
      std::vector<std::string> argv = {(bin / "mtg_agent").string(), "--agent", spec};
      // The one agent that plays the answers; no other agent process gets their key.
      if (spec == agents::kOracleAgent) argv.insert(argv.end(), {"--truth-key-file", truth_key});
      supervisor_.start(name, with(argv));
    } else if (spec == agents::kHumanAgent) {
      std::vector<std::string> argv = {(bin / "mtg_human_agent").string(), "--host", config_.play_host, "--port",
                                       std::to_string(config_.play_port)};
      if (!web::is_loopback(config_.play_host)) {
        // Beyond this machine the page needs a token: drawn here, handed over in a file of the
        // run's own (mode 600), never on a command line others can read.
        play_token_ = web::random_token();
        const fs::path file = dir_ / "play.token";
        web::write_token_file(file.string(), play_token_);
        argv.insert(argv.end(), {"--token-file", file.string()});
      }
      if (!config_.play_socket.empty()) argv.insert(argv.end(), {"--unix-socket", config_.play_socket});
      supervisor_.start(name, with(argv));
    } else if (vlm::is_model_spec(spec)) {
      // As many calls in flight as episodes, unless the settings say otherwise.
      std::vector<std::string> argv = {(bin / "mtg_vlm_agent").string(), "--agent", spec, "--workers",
                                       std::to_string(config_.parallel)};
      argv.insert(argv.end(), config_.vlm_args.begin(), config_.vlm_args.end());
      supervisor_.start(name, with(argv));
      model_agents = true;
    } else {
      throw Error("unknown agent '" + spec + "' (oracle, random, replay:<run>, script:<file>, human, openai:<model>, "
                  "anthropic:<model>, gemini:<model>, openai-compatible:<url>:<model>)");
    }
    agent_process_[spec] = name;
    names_.push_back(name);
  }
  if (model_agents && config_.governor) {
    supervisor_.start("governor", with({(bin / "mtg_governor").string()}));
    names_.push_back("governor");
  }
  wait_ready(names_, 60.0);
  if (std::find(config_.agents.begin(), config_.agents.end(), agents::kHumanAgent) != config_.agents.end()) {
    // Now the page answers: say where it is (mtg play).
    std::printf("play in the browser: %s\n",
                web::page_url({config_.play_host, config_.play_port, play_token_}).c_str());
    std::fflush(stdout);
  }
  return {};
}

void LocalRuntime::wait_ready(const std::vector<std::string>& names, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  std::map<std::string, int> deaths;
  while (Clock::now() < deadline) {
    bool all = true;
    for (const auto& n : names) all = all && last_beat_.count(supervisor_.pid(n)) != 0;
    if (all) return;
    bus_.handle_once(50);
    for (const auto& died : supervisor_.poll()) {
      // A process that cannot start (no recording file, a broken dataset) says why in its log.
      const fs::path log = dir_ / "logs" / (died + ".log");
      if (++deaths[died] >= 3) throw Error(died + " dies as it starts: " + last_line_of(log) + " (" + log.string() + ")");
      log::warn(died + " died while starting");
    }
  }
  std::string missing;
  for (const auto& n : names) {
    if (last_beat_.count(supervisor_.pid(n)) == 0) missing += " " + n;
  }
  throw Error("processes not ready after " + std::to_string(static_cast<int>(timeout_s)) + " s:" + missing +
              " (their logs are in " + (dir_ / "logs").string() + ")");
}

int LocalRuntime::free_slots() const { return config_.parallel - static_cast<int>(in_flight_.size()); }

void LocalRuntime::launch(const EpisodeLaunch& launch) {
  const mtg::episode_start_t& start = launch.start;
  Flight f;
  f.attempt = start.header.attempt;
  f.agent = start.agent;
  f.last_activity = Clock::now();
  in_flight_[bus::episode_of(start.header)] = f;
  bus_.publish(bus::kEpisodeTruth, launch.truth);
  bus_.publish(bus::kEpisodeStart, start);
}

void LocalRuntime::drop(bus::EpisodeId episode_id, int attempt) {
  const auto it = in_flight_.find(episode_id);
  if (it != in_flight_.end() && it->second.attempt == attempt) in_flight_.erase(it);
}

void LocalRuntime::poll(int timeout_ms, LaunchSink& sink) {
  sink_ = &sink;
  kill_hung();
  handle_deaths(sink);
  if (bus_.handle_once(timeout_ms)) {
    while (bus_.handle_once(0)) {
    }
  }
  check_timeouts(sink);
  sink_ = nullptr;
}

void LocalRuntime::finish(std::map<bus::EpisodeId, Flight>::iterator flight) {
  const mtg::episode_result_t result = *flight->second.result;
  in_flight_.erase(flight);
  sink_->on_result(result, "", nullptr);
}

void LocalRuntime::fail(bus::EpisodeId episode_id, const std::string& why, LaunchSink& sink) {
  const auto it = in_flight_.find(episode_id);
  if (it == in_flight_.end()) return;
  const int attempt = it->second.attempt;
  in_flight_.erase(it);
  sink.on_failure(episode_id, attempt, why);
}

void LocalRuntime::touch(const mtg::header_t& h) {
  if (h.run_id != config_.run_id) return;
  const auto it = in_flight_.find(bus::episode_of(h));
  if (it != in_flight_.end() && it->second.attempt == h.attempt) it->second.last_activity = Clock::now();
}

void LocalRuntime::check_timeouts(LaunchSink& sink) {
  std::vector<bus::EpisodeId> stuck;
  for (const auto& [id, f] : in_flight_) {
    if (std::chrono::duration<double>(Clock::now() - f.last_activity).count() > config_.episode_timeout_s) {
      stuck.push_back(id);
    }
  }
  for (const auto id : stuck) {
    fail(id, "no message for " + std::to_string(static_cast<int>(config_.episode_timeout_s)) + " s", sink);
  }
}

void LocalRuntime::kill_hung() {
  const auto now = Clock::now();
  const HangLimits limits = hang_limits(config_.episode_timeout_s);
  auto check = [&](const std::string& name) {
    const pid_t pid = supervisor_.pid(name);
    const auto beat = last_beat_.find(static_cast<int>(pid));
    if (pid <= 0 || beat == last_beat_.end()) return;  // not started, or not ready yet (wait_ready's)
    const double silent = std::chrono::duration<double>(now - beat->second).count();
    Watch& watch = watched_[static_cast<int>(pid)];
    if (silent <= 1.5) {  // beating: nothing to look at (a beat a second; /proc is read only for the silent)
      watch = Watch{};
      return;
    }
    // Look at the main thread at most twice a second while it is silent.
    if (watch.looked == Clock::time_point{} || now - watch.looked >= std::chrono::milliseconds(500)) {
      const auto activity = main_thread_activity(pid);
      if (!activity) return;  // gone: handle_deaths sees it
      // The first look of a silence has nothing to compare the CPU time with: only the state counts.
      const bool first = watch.looked == Clock::time_point{};
      if (made_progress(first ? ThreadActivity{'?', activity->cpu_seconds} : watch.last, *activity)) watch.progress = now;
      watch.last = *activity;
      watch.looked = now;
    }
    const Quiet quiet{silent, std::chrono::duration<double>(now - std::max(watch.progress, beat->second)).count(),
                      watch.last.state == 'T' || watch.last.state == 't'};
    const Silence verdict = classify(quiet, limits);
    const std::string who = name + " (pid " + std::to_string(pid) + ")";
    const std::string secs = std::to_string(static_cast<int>(silent));
    if (verdict == Silence::kSlow && !watch.said_slow) {
      watch.said_slow = true;
      log::warn(who + " sent no heartbeat for " + secs + " s but its main thread is working: slow, not hung; left " +
                "alone for up to " + std::to_string(static_cast<int>(limits.runaway_after_s)) + " s of silence");
    }
    if (verdict != Silence::kHung && verdict != Silence::kRunaway) return;
    log::warn(who + " sent no heartbeat for " + secs + " s " +
              (verdict == Silence::kHung ? std::string("and did no work (") + watch.last.state + "): it hangs"
                                         : std::string("while working all along: taken for looping")) +
              "; killed, to be restarted");
    ::kill(pid, SIGKILL);
    last_beat_.erase(beat);
    watched_.erase(static_cast<int>(pid));
  };
  for (const std::string& name : names_) check(name);
  if (recorder_beats()) check("recorder");
}

void LocalRuntime::handle_deaths(LaunchSink& sink) {
  const auto died = supervisor_.poll();
  if (died.empty()) return;
  std::set<std::string> affected_agents;
  bool all = false;
  for (const auto& name : died) {
    // A recorder that keeps dying before it records anything cannot record this run: say so,
    // rather than run episodes nobody can replay.
    if (name == "recorder" && ++recorder_deaths_since_ack_ >= 3 && recorder_acks()) {
      throw Error("the recorder died 3 times in a row without recording a result (see " +
                  (dir_ / "logs" / "recorder.log").string() + "): the run cannot be recorded; it resumes once fixed");
    }
    // The governor holds no episode: its restart only delays calls. A renderer's neither: the
    // scene-graph service asks its successor for what it was drawing (episode_host.h).
    if (name == "scene_graph" || name == "judge" || name == "recorder") all = true;
    for (const auto& [spec, process] : agent_process_) {
      if (process == name) affected_agents.insert(spec);
    }
  }
  std::vector<bus::EpisodeId> failed;
  for (const auto& [id, f] : in_flight_) {
    if (all || affected_agents.count(f.agent)) failed.push_back(id);
  }
  std::vector<std::string> restarted;
  for (const auto& name : died) {
    if (name != "recorder" || recorder_beats()) restarted.push_back(name);  // lcm-logger sends no heartbeat
  }
  wait_ready(restarted, 60.0);
  for (const auto id : failed) fail(id, "a process it depended on was restarted", sink);
}

void LocalRuntime::close() {
  if (!open_) return;
  open_ = false;
  mtg::run_control_t stop{};
  stop.header = stamp_.next({}, 0, "control");
  stop.command = "shutdown";
  bus_.publish(bus::kControl, stop);
  for (const auto& name : names_) supervisor_.stop(name, SIGTERM, 3000);
  supervisor_.stop("recorder", SIGINT, 3000);  // it records what is queued, then closes
}

}  // namespace mtg::orchestrator
