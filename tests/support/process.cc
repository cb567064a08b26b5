#include "tests/support/process.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <stdexcept>
#include <thread>

#include "bus/process/subprocess.h"

namespace mtg::testing {

std::string bin(const std::string& name) { return std::string(MTG_BIN_DIR) + "/" + name; }

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_file)
    : pid_(process::spawn_process(argv, log_file, SIGKILL)) {}  // SIGKILL: never outlive the test

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

namespace mtg::testing {

pid_t descendant_pid(pid_t ancestor, const std::string& program) {
  namespace fs = std::filesystem;
  auto parent_of = [](pid_t pid) -> pid_t {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(stat, line)) return -1;
    // "pid (comm) state ppid ...": comm may hold spaces, so read after the last ')'.
    std::istringstream rest(line.substr(line.rfind(')') + 1));
    char state = 0;
    pid_t ppid = -1;
    rest >> state >> ppid;
    return ppid;
  };
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || !std::isdigit(static_cast<unsigned char>(name[0]))) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    std::ifstream comm(entry.path() / "comm");
    std::string exe;
    if (!std::getline(comm, exe) || exe != program.substr(0, 15)) continue;  // comm keeps 15 characters
    for (pid_t p = parent_of(pid); p > 1; p = parent_of(p)) {
      if (p == ancestor) return pid;
    }
  }
  return -1;
}

}  // namespace mtg::testing

namespace mtg::testing {

int port_in_log(const std::string& log_file, int timeout_ms) {
  const std::regex url(R"(http://127\.0\.0\.1:(\d+)/)");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (std::chrono::steady_clock::now() < deadline) {
    std::ifstream in(log_file);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    std::smatch m;
    if (std::regex_search(text, m, url)) return std::stoi(m[1]);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return -1;
}

}  // namespace mtg::testing
