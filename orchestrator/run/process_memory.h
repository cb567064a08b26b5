#pragma once
// Resident memory and CPU time of a process and of the processes it started, read from /proc (Linux). For
// `mtg bench soak`, `mtg bench pool` and the soak test: telemetry, never used in run logic. Also what a
// process's main thread is doing, for the hang rule (hang_rule.h) only.

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "orchestrator/run/hang_rule.h"

namespace mtg::orchestrator {

struct ProcessMemory {
  pid_t pid = 0;
  /// What the process is in a run: its executable's name without "mtg_" ("judge", "scene_graph",
  /// "recorder"), with the agent for an agent process ("agent:oracle"); "mtg" for the root.
  std::string role;
  double rss_mib = 0.0;  // VmRSS
  double cpu_seconds = 0.0;  // user + system so far (its own, not its children's)
};

/// User + system CPU seconds of `pid` so far (its own, not its children's); 0 when it is gone.
double process_cpu_seconds(pid_t pid);

/// State and CPU time of the main thread of `pid` (the one that runs a service's loop and beats);
/// nullopt when the process is gone.
std::optional<ThreadActivity> main_thread_activity(pid_t pid);

/// `root` and every living descendant of it, in pid order. Processes that end while they are read
/// are left out.
std::vector<ProcessMemory> process_tree_memory(pid_t root);

}  // namespace mtg::orchestrator
