#pragma once
// Starts the local processes of a run and keeps them alive: a process that dies (killed,
// crashed) is restarted with the same command line, and the caller learns which one died so it
// can retry the episodes that process held.

#include <sys/types.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bus/private_network.h"

namespace mtg::orchestrator {

class Supervisor {
 public:
  /// With `network`, every process starts in that network namespace (bus/private_network.h).
  explicit Supervisor(std::filesystem::path log_dir, std::shared_ptr<const bus::PrivateNetwork> network = nullptr)
      : log_dir_(std::move(log_dir)), network_(std::move(network)) {}
  ~Supervisor();
  Supervisor(const Supervisor&) = delete;
  Supervisor& operator=(const Supervisor&) = delete;

  /// Starts `argv` under `name` (stdout/stderr appended to <log_dir>/<name>.log).
  /// @throws mtg::Error if it cannot be started.
  void start(const std::string& name, const std::vector<std::string>& argv, bool restart = true);
  /// Reaps dead processes, restarts those marked for it, returns their names.
  std::vector<std::string> poll();
  pid_t pid(const std::string& name) const;
  /// Sends `signal` to one process and waits up to `timeout_ms` for it to exit (then SIGKILL).
  void stop(const std::string& name, int signal, int timeout_ms);
  /// Stops everything (SIGTERM, then SIGKILL after `timeout_ms`).
  void stop_all(int timeout_ms);
  int restarts() const { return restarts_; }

 private:
  struct Child {
    std::vector<std::string> argv;
    pid_t pid = -1;
    bool restart = true;
  };
  pid_t spawn(const std::string& name, const std::vector<std::string>& argv);

  std::filesystem::path log_dir_;
  std::shared_ptr<const bus::PrivateNetwork> network_;
  std::map<std::string, Child> children_;
  int restarts_ = 0;
};

/// Directory of the running executable (to find the sibling service binaries).
std::filesystem::path executable_dir();

}  // namespace mtg::orchestrator
