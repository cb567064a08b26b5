#include "orchestrator/run/run_namespace.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "agents/vlm/http_relay.h"
#include "bus/private_network.h"
#include "orchestrator/run/page_relay.h"
#include "core/util/json_file.h"
#include "core/util/log.h"

extern char** environ;

namespace mtg::orchestrator {
namespace {

volatile sig_atomic_t g_child = 0;

void forward_signal(int sig) {
  if (g_child > 0) ::kill(static_cast<pid_t>(g_child), sig);
}

// In the child, between fork and exec: report `what` and errno on the pipe, then leave.
[[noreturn]] void fail(int report_fd, const char* what) {
  char buf[256];
  const int n = std::snprintf(buf, sizeof(buf), "%s: %s", what, std::strerror(errno));
  if (n > 0) (void)!::write(report_fd, buf, static_cast<std::size_t>(std::min(n, static_cast<int>(sizeof(buf)) - 1)));
  ::_exit(127);
}

}  // namespace

bool inside_run_namespace() {
  const char* v = std::getenv(kRunNamespaceEnv);
  return v != nullptr && *v != '\0';
}

std::optional<int> run_in_own_namespace(char** argv, PageRelay* page) {
  if (inside_run_namespace()) return std::nullopt;
  vlm::HttpRelayServer relay;
  // Everything the child needs, made before fork: after it only async-signal-safe calls.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string var(*e);
    if (var.rfind(std::string(kRunNamespaceEnv) + "=", 0) == 0 || var.rfind(std::string(vlm::kHttpRelayEnv) + "=", 0) == 0 ||
        var.rfind(std::string(kPlaySocketEnv) + "=", 0) == 0) {
      continue;
    }
    env_strings.push_back(var);
  }
  env_strings.push_back(std::string(kRunNamespaceEnv) + "=1");
  env_strings.push_back(std::string(vlm::kHttpRelayEnv) + "=" + relay.socket_path());
  if (page != nullptr) env_strings.push_back(std::string(kPlaySocketEnv) + "=" + page->socket_path());
  std::vector<char*> envp;
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  const bus::IdMaps maps = bus::own_id_maps();
  const bool as_root = ::geteuid() == 0;
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) return std::nullopt;
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(report[0]);
    ::close(report[1]);
    log::warn("run not isolated (fork failed): it shares this machine's loopback bus");
    return std::nullopt;
  }
  if (child == 0) {
    ::close(report[0]);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // the outer process gone: stop, resumably
    if (::getppid() != parent) ::_exit(1);
    // As root a network namespace alone; otherwise a user namespace that maps us to ourselves.
    if (const char* step = bus::enter_new_network(as_root ? nullptr : &maps)) fail(report[1], step);
    ::execve("/proc/self/exe", argv, envp.data());
    fail(report[1], "exec");
  }
  ::close(report[1]);
  char why[256] = {0};
  ssize_t n;
  do {
    n = ::read(report[0], why, sizeof(why) - 1);
  } while (n < 0 && errno == EINTR);
  ::close(report[0]);
  if (n > 0) {
    int ignored = 0;
    ::waitpid(child, &ignored, 0);
    log::warn(std::string("run not isolated (") + why +
              "): it shares this machine's loopback bus; its processes still ignore other runs");
    return std::nullopt;
  }
  relay.start();
  if (page != nullptr) page->start();
  g_child = child;
  struct sigaction sa{};
  sa.sa_handler = forward_signal;
  ::sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  g_child = 0;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) {
    // The inner process stops on SIGINT/SIGTERM by itself, saying how to resume; a signal that
    // ends it (kill -9, a crash) leaves that line unsaid, so it is said here.
    std::fprintf(stderr, "mtg: the run's orchestrator was killed (signal %d, %s); finished episodes are kept: run the "
                 "same command again to resume\n", WTERMSIG(status), ::strsignal(WTERMSIG(status)));
    return 128 + WTERMSIG(status);
  }
  return 1;
}

void write_bus_file(const std::filesystem::path& dir, const std::string& url, const bus::PrivateNetwork* network) {
  nlohmann::json bus = {{"url", url}, {"pid", static_cast<long>(::getpid())}};
  if (network != nullptr) {
    bus["own_namespace"] = true;
    bus["netns"] = network->path();  // kept open by this process, beside its own namespace
    bus["user_namespace"] = network->in_user_namespace();
  } else {
    bus["own_namespace"] = inside_run_namespace();
    bus["user_namespace"] = inside_run_namespace() && ::geteuid() != 0;
  }
  write_json_file(dir / "bus.json", bus);
}

}  // namespace mtg::orchestrator
