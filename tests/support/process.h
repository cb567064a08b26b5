#pragma once
// Child processes for integration tests: start a project executable, wait for it, kill it.
// The destructor kills what is still running, so a failing test never leaves processes behind.

#include <sys/types.h>

#include <string>
#include <vector>

namespace mtg::testing {

/// Path of an executable of this build (build/bin/<name>).
std::string bin(const std::string& name);

class ChildProcess {
 public:
  /// Starts argv[0] with the given arguments; stdout/stderr go to `log_file` ("" = inherit).
  explicit ChildProcess(const std::vector<std::string>& argv, const std::string& log_file = "");
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  /// Sends `signal` (default SIGKILL) and reaps.
  void kill(int signal = 9);
  /// Waits up to `timeout_ms`; returns the exit status (or -1 on timeout / killed by a signal).
  int wait(int timeout_ms);

 private:
  pid_t pid_ = -1;
  bool reaped_ = false;
  int status_ = 0;
};

/// The pid of a running descendant of `ancestor` whose executable is named `program` (e.g.
/// "mtg_judge"), or -1. A run's processes live in a network namespace of their own, so tests find
/// them through the process tree rather than through their heartbeats.
pid_t descendant_pid(pid_t ancestor, const std::string& program);

/// Waits for "http://127.0.0.1:<port>/" in a child's log (`mtg view`, `mtg play` print where
/// they listen); returns the port, or -1 after `timeout_ms`.
int port_in_log(const std::string& log_file, int timeout_ms);

}  // namespace mtg::testing
