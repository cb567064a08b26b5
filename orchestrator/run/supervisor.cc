#include "orchestrator/run/supervisor.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "bus/process/subprocess.h"
#include "core/util/error.h"
#include "core/util/log.h"

namespace mtg::orchestrator {

std::filesystem::path executable_dir() {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::current_path() : self.parent_path();
}

Supervisor::~Supervisor() { stop_all(2000); }

pid_t Supervisor::spawn(const std::string& name, const std::vector<std::string>& argv) {
  std::filesystem::create_directories(log_dir_);
  return process::spawn_process(argv, (log_dir_ / (name + ".log")).string(), SIGTERM, network_.get());
}

void Supervisor::start(const std::string& name, const std::vector<std::string>& argv, bool restart) {
  children_[name] = Child{argv, spawn(name, argv), restart};
}

std::vector<std::string> Supervisor::poll() {
  std::vector<std::string> died;
  for (auto& [name, child] : children_) {
    if (child.pid < 0) continue;
    int status = 0;
    if (waitpid(child.pid, &status, WNOHANG) != child.pid) continue;
    died.push_back(name);
    log::warn(name + " (pid " + std::to_string(child.pid) + ") exited" +
              (WIFSIGNALED(status) ? " on signal " + std::to_string(WTERMSIG(status))
                                   : " with status " + std::to_string(WEXITSTATUS(status))) +
              (child.restart ? "; restarting it" : ""));
    child.pid = -1;
    if (child.restart) {
      child.pid = spawn(name, child.argv);
      ++restarts_;
    }
  }
  return died;
}

pid_t Supervisor::pid(const std::string& name) const {
  const auto it = children_.find(name);
  return it == children_.end() ? -1 : it->second.pid;
}

void Supervisor::stop(const std::string& name, int signal, int timeout_ms) {
  auto it = children_.find(name);
  if (it == children_.end() || it->second.pid < 0) return;
  Child& child = it->second;
  child.restart = false;
  ::kill(child.pid, signal);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  int status = 0;
  while (waitpid(child.pid, &status, WNOHANG) != child.pid) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(child.pid, SIGKILL);
      waitpid(child.pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  child.pid = -1;
}

void Supervisor::stop_all(int timeout_ms) {
  for (auto& [name, child] : children_) {
    if (child.pid >= 0) {
      child.restart = false;
      ::kill(child.pid, SIGTERM);
    }
  }
  for (auto& [name, child] : children_) stop(name, SIGTERM, timeout_ms);
}

}  // namespace mtg::orchestrator
