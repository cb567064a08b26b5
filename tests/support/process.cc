#include "tests/support/process.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <thread>

#include "core/util/subprocess.h"

namespace mtg::testing {

std::string bin(const std::string& name) { return std::string(MTG_BIN_DIR) + "/" + name; }

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_file)
    : pid_(spawn_process(argv, log_file, SIGKILL)) {}  // SIGKILL: never outlive the test

ChildProcess::~ChildProcess() {
  if (!reaped_) kill(SIGKILL);
}

bool ChildProcess::running() {
  if (reaped_) return false;
  const pid_t r = waitpid(pid_, &status_, WNOHANG);
  if (r == pid_) reaped_ = true;
  return !reaped_;
}

void ChildProcess::kill(int signal) {
  if (reaped_) return;
  ::kill(pid_, signal);
  waitpid(pid_, &status_, 0);
  reaped_ = true;
}

int ChildProcess::wait(int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (running()) {
    if (std::chrono::steady_clock::now() > deadline) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
}

}  // namespace mtg::testing
