#pragma once
// Where a run's episode attempts execute. The run engine (run_engine.h) decides what runs and
// keeps the books (retries, results written once); a launcher only starts attempts and reports
// back what became of them:
//   - LocalRuntime (local_runtime.h): the run's processes on this machine, on one bus;
//   - LeaseLauncher (orchestrator/remote/lease_launcher.h): workers on other machines, by lease.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bus/episode_id.h"
#include "bus/recording_ref.h"
#include "mtg/episode_result_t.hpp"
#include "mtg/episode_start_t.hpp"
#include "mtg/episode_truth_t.hpp"

namespace mtg::orchestrator {

/// What starts one episode attempt: the start every process of the run sees, and the truth
/// (goal, oracle plan) that only the judge, the scene-graph service and the oracle may see. A
/// launcher publishes the truth first, on its own channel.
struct EpisodeLaunch {
  mtg::episode_start_t start;
  mtg::episode_truth_t truth;
};

/// Progress of a run as the engine counts it (a coordinator announces it; telemetry only).
struct RunCounts {
  std::int64_t planned = 0;
  std::int64_t finished = 0;  // rows in results.sqlite, scored or error
  std::int64_t scored = 0;
  std::int64_t successes = 0;
  double ip_sum = 0.0;
  std::int64_t errors = 0;
  int in_flight = 0;
};

/// What a launcher reports. Called from inside Launcher::poll().
class LaunchSink {
 public:
  virtual ~LaunchSink() = default;
  /// The judge's verdict on an attempt (any cause, including transport_error and
  /// provider_error); `worker` is who ran it ("" on this machine); `recording` where the
  /// attempt's recording was kept (null: in the run folder's own recording), stored with the
  /// verdict in one transaction.
  virtual void on_result(const mtg::episode_result_t& result, const std::string& worker,
                         const bus::RecordingRef* recording) = 0;
  /// The attempt is lost without a verdict (a process died, no news for too long, a worker
  /// vanished); the engine decides whether to try again.
  virtual void on_failure(bus::EpisodeId episode, int attempt, const std::string& why) = 0;
  /// An agent stopped for good (authentication, quota, billing): no more of its episodes.
  virtual void on_agent_stopped(const std::string& agent, const std::string& why) = 0;
};

/// An attempt that was already running when the launcher opened (a restarted coordinator adopts
/// the leases its workers still hold).
struct AdoptedAttempt {
  bus::EpisodeId episode;
  int attempt = 0;
};

class Launcher {
 public:
  virtual ~Launcher() = default;
  /// Starts what the run needs; returns attempts already in flight.
  /// @throws mtg::Error if the run cannot start (processes never ready, no worker).
  virtual std::vector<AdoptedAttempt> open() = 0;
  /// How many more attempts may start now.
  virtual int free_slots() const = 0;
  /// The attempt number an episode's next try should use (above every one used before).
  virtual int next_attempt(bus::EpisodeId episode) const = 0;
  virtual void launch(const EpisodeLaunch& launch) = 0;
  /// Forgets an attempt the engine no longer wants (its agent stopped, it was given up).
  virtual void drop(bus::EpisodeId episode, int attempt) = 0;
  /// Waits up to `timeout_ms` for news and reports it to `sink`.
  virtual void poll(int timeout_ms, LaunchSink& sink) = 0;
  /// Stops what open() started.
  virtual void close() = 0;
  /// Processes restarted so far (telemetry).
  virtual int restarts() const = 0;
};

}  // namespace mtg::orchestrator
