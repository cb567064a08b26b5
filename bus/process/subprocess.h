#pragma once
// Starting a child process that cannot outlive its parent: the kernel sends it
// `parent_death_signal` when the parent dies, so a killed orchestrator (or test) never leaves
// services behind that would answer a resumed run twice.

#include <sys/types.h>

#include <string>
#include <vector>

namespace mtg::bus {
class PrivateNetwork;
}

namespace mtg::process {

/// Starts argv[0] (an absolute path) with `argv`; stdout and stderr are appended to `log_file`
/// ("" = inherited). With `network`, the child runs in that network namespace. Returns the
/// child's pid; the caller reaps it.
/// @throws mtg::Error if the process cannot be forked. A failed exec, or a namespace the child
/// cannot enter (said in its log), exits the child with 127.
pid_t spawn_process(const std::vector<std::string>& argv, const std::string& log_file, int parent_death_signal,
                    const bus::PrivateNetwork* network = nullptr);

struct CommandOutput {
  int exit_code = -1;  // -1 when it did not exit normally
  std::string output;  // stdout and stderr, interleaved
};

/// Replaces this process with argv[0] (an absolute path). @throws mtg::Error if exec fails.
[[noreturn]] void exec_process(const std::vector<std::string>& argv);

/// Runs a short command (argv[0] is looked up on the PATH) to its end and returns what it printed.
/// @throws mtg::Error if it cannot be started (exit code 127 from the child means not found).
CommandOutput run_command(const std::vector<std::string>& argv);

}  // namespace mtg::process
