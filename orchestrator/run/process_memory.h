#pragma once
// Resident memory of a process and of the processes it started, read from /proc (Linux). For
// `mtg bench soak` and its test: telemetry, never used in run logic.

#include <sys/types.h>

#include <string>
#include <vector>

namespace mtg::orchestrator {

struct ProcessMemory {
  pid_t pid = 0;
  /// What the process is in a run: its executable's name without "mtg_" ("judge", "scene_graph",
  /// "recorder"), with the agent for an agent process ("agent:oracle"); "mtg" for the root.
  std::string role;
  double rss_mib = 0.0;  // VmRSS
};

/// `root` and every living descendant of it, in pid order. Processes that end while they are read
/// are left out.
std::vector<ProcessMemory> process_tree_memory(pid_t root);

}  // namespace mtg::orchestrator
