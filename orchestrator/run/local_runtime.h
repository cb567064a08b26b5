#pragma once
// The run's processes on this machine, on one bus: the recorder, the scene-graph service, the
// judge, the renderer when images are on, one process per agent, and the rate governor for model
// agents. It starts episode attempts, watches them, and reports what became of each:
//   - a result from the judge (any cause), once the recorder has written it to the recording;
//   - a failure when no message about the attempt came for episode_timeout_s, when a service
//     reported an error about it, or when a process it depended on died (that process is
//     restarted first; a recorder that died before acknowledging an attempt's result means the
//     attempt may be missing from the recording, so it runs again);
//   - a stopped agent when a model agent reports a fatal error (authentication, quota, billing).
// A process that stops sending heartbeats (stopped, deadlocked, swapped out) for most of an
// episode time-out is killed, and so restarted as a dead one is: its attempts run again on a
// live one instead of timing out against it until they are given up.
// `mtg run` uses it directly; `mtg worker` uses one per run it joins.

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus/bus.h"
#include "bus/header.h"
#include "bus/private_network.h"
#include "core/graph/options.h"
#include "orchestrator/run/hang_rule.h"
#include "orchestrator/run/launcher.h"
#include "orchestrator/run/supervisor.h"

namespace mtg::orchestrator {

struct RuntimeConfig {
  std::string run_id;
  std::string bus_url;
  std::string profile = "replica_cad";
  /// The services build their graphs so, as the run's tasks were planned (RunPlan::platform_rules).
  graph::PlatformRules platform_rules = graph::PlatformRules::kReachedAndSeen;
  bool render = false;
  /// Renderer processes when images are on (core/render/render_pool.h; 0 = one per four cores,
  /// at least one per GPU). Each host of a multi-host run chooses its own.
  int renderers = 0;
  int image_width = 640;
  int image_height = 480;
  std::string image_encoding = "png";
  std::vector<std::string> agents;    // agent specs; one process each
  std::vector<std::string> vlm_args;  // for every model adapter (agents/vlm/options.h)
  int parallel = 4;                   // attempts at once
  double episode_timeout_s = 60.0;
  /// "mtg" (mtg_recorder) or "lcm-logger" (the stock tool; drops bursts on a busy machine).
  std::string recorder = "mtg";
  /// Start the rate governor when a model agent runs. A worker does not: the coordinator's
  /// governor serves every host, so the limits hold for the whole run.
  bool governor = true;
  /// What the task set was made from (scene::fingerprints_from_json; "" = unchecked): a worker
  /// compares its own dataset with it before it joins, unless mismatches are allowed.
  std::string dataset_json;
  bool allow_data_mismatch = false;
  std::string data_dir;  // the run's dataset path ("" = the default search), as in episode starts
  std::string play_host = "127.0.0.1";  // the human agent's play page (`mtg play`)
  int play_port = 8780;
  /// "" or a Unix socket to serve the page on, relayed from play_host:play_port by the outer
  /// `mtg play` (page_relay.h).
  std::string play_socket = "";
  /// Attempt numbers one invocation may use (the plan's max_attempts): invocation k of a run
  /// (its recording bus-<k>.lcmlog) numbers its attempts from k times this, so a resumed episode
  /// never repeats an attempt an earlier invocation recorded.
  int attempts_per_invocation = 3;
  /// The key file of a shared bus whose secret the run's answer key derives from (a worker's
  /// runtime: every host seals and opens with the same key); "" = a key of the run's own.
  /// Either way it is kept in the run folder's truth.key (bus/truth_seal.h).
  std::string truth_secret_file = "";
  /// The network namespace the run's bus and processes live in (a worker's, bus/private_network.h);
  /// null: this process's own (`mtg run` is inside a namespace of the run's already).
  std::shared_ptr<const bus::PrivateNetwork> network;
};

class LocalRuntime final : public Launcher {
 public:
  /// Recordings (bus-<k>.lcmlog) and process logs (logs/) go to `dir`.
  LocalRuntime(RuntimeConfig config, std::filesystem::path dir);

  std::vector<AdoptedAttempt> open() override;
  int free_slots() const override;
  int next_attempt(bus::EpisodeId) const override { return first_attempt_; }
  void launch(const EpisodeLaunch& launch) override;
  void drop(bus::EpisodeId episode_id, int attempt) override;
  void poll(int timeout_ms, LaunchSink& sink) override;
  void close() override;
  int restarts() const override { return supervisor_.restarts(); }

  int in_flight() const { return static_cast<int>(in_flight_.size()); }
  /// The bus the run's processes share (a worker records and bridges from it).
  bus::Bus& bus() { return bus_; }

 private:
  using Clock = std::chrono::steady_clock;
  struct Flight {
    int attempt = 0;
    std::string agent;
    Clock::time_point last_activity;
    /// The judge's result, held until the recorder says the attempt is in the recording.
    std::optional<mtg::episode_result_t> result;
    bool recorded = false;  // the recorder's acknowledgement came (it may come first)
  };

  void subscribe();
  void wait_ready(const std::vector<std::string>& names, double timeout_s);
  void handle_deaths(LaunchSink& sink);
  void check_timeouts(LaunchSink& sink);
  /// Kills the processes hung or looping by the hang rule (hang_rule.h); handle_deaths restarts them.
  void kill_hung();
  void fail(bus::EpisodeId episode_id, const std::string& why, LaunchSink& sink);
  /// Hands the flight's result to the sink and forgets the flight.
  void finish(std::map<bus::EpisodeId, Flight>::iterator flight);
  void touch(const mtg::header_t& h);
  bool recorder_beats() const { return config_.recorder != "lcm-logger"; }
  /// The mtg recorder acknowledges every result it writes; lcm-logger does not.
  bool recorder_acks() const { return config_.recorder == "mtg"; }

  RuntimeConfig config_;
  std::filesystem::path dir_;
  bus::Bus bus_;
  bus::HeaderStamper stamp_;
  Supervisor supervisor_;
  std::vector<std::string> names_;                   // processes that heartbeat, but the recorder
  std::map<std::string, std::string> agent_process_; // agent spec -> process name
  std::string play_token_;                           // the play page's token ("" on loopback)
  int first_attempt_ = 0;                            // of this invocation (RuntimeConfig::attempts_per_invocation)
  // The last heartbeat of each process by pid: one heard is ready (wait_ready), one silent too long hangs.
  std::map<int, std::chrono::steady_clock::time_point> last_beat_;
  /// What the hang rule saw of a silent process's main thread, by pid.
  struct Watch {
    Clock::time_point looked{};    // when /proc was last read (epoch: not yet in this silence)
    Clock::time_point progress{};  // the last sign of work
    ThreadActivity last{};
    bool said_slow = false;
  };
  std::map<int, Watch> watched_;
  std::map<bus::EpisodeId, Flight> in_flight_;
  LaunchSink* sink_ = nullptr;  // during poll()
  bool open_ = false;
  int recorder_deaths_since_ack_ = 0;
};

}  // namespace mtg::orchestrator
