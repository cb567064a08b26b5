#pragma once
// When a silent service is hung rather than slow. Every service beats once a second from its main
// loop, so a beat also waits for the work in hand (a frame under heavy load, a large scene). Silence
// alone therefore cannot tell a renderer that needs 20 s for a frame on a machine at load 13 from
// one stopped or deadlocked: the rule also asks whether the main thread makes progress (uses CPU,
// or waits on the disk). A stopped or blocked service is hung after `hang_after_s`; a working one
// is slow and left alone until `runaway_after_s` of silence, past which it is taken for looping.
// docs/runtime.md, "Hung processes", says the limits.

namespace mtg::orchestrator {

enum class Silence {
  kBeating,   // heard from recently
  kSlow,      // silent, but its main thread works: left alone
  kHung,      // silent and not working (stopped, blocked): killed and restarted
  kRunaway,   // silent and working for too long (a loop): killed and restarted
};

const char* to_string(Silence s);

struct HangLimits {
  double hang_after_s = 3.0;     // silence and no progress
  double runaway_after_s = 6.0;  // silence despite progress
};

/// The limits for a run whose episodes time out after `episode_timeout_s` without a message: a hung
/// service after 80 % of it (at least 3 s), so its attempts move to its successor before they time
/// out against it; a working one after twice it (its episodes have timed out and been retried by
/// then, so longer only delays the retries).
HangLimits hang_limits(double episode_timeout_s);

/// What the main thread of a process was doing when last looked at (/proc/<pid>/task/<pid>/stat).
struct ThreadActivity {
  char state = '?';         // proc(5): R running, S sleeping, D disk, T stopped, Z zombie, ...
  double cpu_seconds = 0.0; // user + system so far
};

/// The silence of one process as seen so far.
struct Quiet {
  double since_beat_s = 0.0;      // since its last heartbeat
  double since_progress_s = 0.0;  // since its last heartbeat or the last sign of work
  bool stopped = false;           // stopped by a signal or a tracer (state T or t)
};

/// Pure: what to do about a process that has been quiet as `q` says.
Silence classify(const Quiet& q, const HangLimits& limits);

/// Whether the main thread worked between two looks: it used CPU, or it is running or waiting on
/// the disk now (a thread starved of CPU on a loaded machine may show no tick in half a second).
bool made_progress(const ThreadActivity& before, const ThreadActivity& now);

}  // namespace mtg::orchestrator
