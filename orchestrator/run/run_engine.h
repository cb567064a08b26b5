#pragma once
// Runs a plan: hands out episodes K at a time to a launcher (launcher.h) -- the run's processes
// on this machine, or with plan.remote the workers of other machines by lease -- writes each final
// result once to results.sqlite, and keeps going through failures:
//   - a result with cause transport_error (the judge saw a lost message) or provider_error (the
//     model's API failed after the adapter's own retries), or no message about an episode for
//     episode_timeout_s, retries the episode (a new attempt, fresh state everywhere);
//   - a model agent that reports a fatal error (authentication, quota, billing) gets no more
//     episodes; what it has not finished stays unfinished for a later resume;
//   - a process that dies is restarted, and the episodes it held are retried once it is back; a
//     worker that stops renewing its leases loses them, and its episodes run elsewhere;
//   - after max_attempts an episode is recorded with status "error" (excluded from SR and IP).
// A killed orchestrator loses nothing: finished episodes are on disk; the next run resumes.

#include <atomic>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/tasks/task.h"
#include "orchestrator/remote/remote_options.h"
#include "orchestrator/run/run_plan.h"

namespace mtg::orchestrator {

struct RunSummary {
  std::int64_t planned = 0;
  std::int64_t already_done = 0;   // finished before this invocation (resume)
  std::int64_t completed = 0;      // finished now
  std::int64_t errors = 0;         // recorded with status "error"
  std::int64_t retries = 0;
  int restarts = 0;
  double seconds = 0.0;            // the whole invocation (telemetry)
  double episode_seconds = 0.0;    // first episode handed out to last result (telemetry)
  /// CPU (user + system) of this process and every process it started and has ended, over the
  /// invocation: the run's services on this machine, or a coordinator's governor (telemetry).
  double cpu_seconds = 0.0;
  bool interrupted = false;
  /// Agents that stopped (authentication, quota, billing): agent spec -> why. Their episodes
  /// not yet finished stay unfinished, so the same command resumes them once fixed.
  std::map<std::string, std::string> stopped_agents;
  std::int64_t not_run = 0;        // episodes left unfinished because their agent stopped
  /// Set when the budget (EngineOptions::budget) stopped new episodes from starting: the one
  /// line that says so. The episodes not started are simply not run; a resume runs them.
  std::string budget_stop;
  std::int64_t not_started = 0;    // episodes the budget left for a resume
};

/// --max-cost (docs/vlm.md, "Cost before spending"): no episode starts once what the run has
/// spent (every invocation's rows in results.sqlite, and the attempts this one retried) plus what
/// the episodes in flight are expected to cost reaches the cap. An episode in flight counts at
/// its agent's average spent per scored episode of the run, or, until its agent has one, at the
/// estimate's expected cost (run_estimate.h). A permission of the invocation, like
/// allow_data_mismatch, never part of the plan.
struct Budget {
  double max_cost_usd = 0.0;  // 0 = no cap
  std::map<std::string, double> expected_episode_cost_usd;  // agent spec -> US$
};

struct EngineOptions {
  bool progress = true;  // live progress bar on stderr
  /// "mtg" (mtg_recorder, the default) or "lcm-logger" (the stock tool, which drops bursts of
  /// more than 30 messages when its process is starved: docs/runtime.md, "Recording").
  std::string recorder = "mtg";
  /// Renderer processes on this machine when the plan renders (0 = render::default_renderers).
  int renderers = 0;
  /// Arguments for every model adapter process (agents/vlm/options.h, VlmOptions::to_args).
  std::vector<std::string> vlm_args;
  /// With plan.remote: how the coordinator deals with workers.
  remote::RemoteOptions remote;
  /// The task set's dataset fingerprints of the plan's scenes (scene::to_json), for workers.
  std::string dataset_json;
  /// Where the human agent serves its play page (`mtg play`).
  std::string play_host = "127.0.0.1";
  int play_port = 8780;
  std::string play_socket = "";  // or the Unix socket the page is served on (a run in its own namespace)
  /// When set, the number of results this invocation has stored so far, for an observer in
  /// another thread (`mtg bench soak` samples by it instead of querying results.sqlite, whose
  /// page cache would count in the orchestrator's memory it measures).
  std::atomic<std::int64_t>* stored = nullptr;
  Budget budget{};
  /// `mtg play`: once every episode is done, the services (the play page with the last verdict
  /// and the score) stay up until a stop signal, so the person sees how the last episode went.
  bool hold_after_last = false;
};

/// @throws mtg::Error if the processes cannot be started or never become ready.
RunSummary run_plan(const RunPlan& plan, const std::filesystem::path& run_dir,
                    const std::map<std::string, tasks::Task>& tasks, const EngineOptions& options = {});

class Launcher;
/// The engine alone over `launcher` (run_plan picks the launcher; tests script one).
RunSummary run_plan_with(const RunPlan& plan, const std::filesystem::path& run_dir,
                         const std::map<std::string, tasks::Task>& tasks, Launcher& launcher,
                         const EngineOptions& options = {});

}  // namespace mtg::orchestrator
