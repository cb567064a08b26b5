#include "orchestrator/run/run_namespace.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <net/if.h>
#include <net/route.h>
#include <netinet/in.h>
#include <sched.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/prctl.h>
#include <sys/socket.h>
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
#include "orchestrator/run/page_relay.h"
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

bool write_file(const char* path, const char* text) {
  const int fd = ::open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const auto n = static_cast<ssize_t>(std::strlen(text));
  const bool ok = ::write(fd, text, static_cast<std::size_t>(n)) == n;
  ::close(fd);
  return ok;
}

// Loopback up and 224.0.0.0/4 routed through it, in the current network namespace.
bool configure_loopback() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, "lo", IFNAMSIZ - 1);
  bool ok = ::ioctl(fd, SIOCGIFFLAGS, &ifr) == 0;
  ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP | IFF_RUNNING);
  ok = ok && ::ioctl(fd, SIOCSIFFLAGS, &ifr) == 0;
  rtentry rt{};
  auto* dst = reinterpret_cast<sockaddr_in*>(&rt.rt_dst);
  auto* mask = reinterpret_cast<sockaddr_in*>(&rt.rt_genmask);
  dst->sin_family = mask->sin_family = AF_INET;
  dst->sin_addr.s_addr = htonl(0xE0000000u);   // 224.0.0.0
  mask->sin_addr.s_addr = htonl(0xF0000000u);  // /4
  rt.rt_flags = RTF_UP;
  char lo[] = "lo";
  rt.rt_dev = lo;
  ok = ok && ::ioctl(fd, SIOCADDRT, &rt) == 0;
  ::close(fd);
  return ok;
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
  const uid_t uid = ::geteuid();
  const gid_t gid = ::getegid();
  const std::string uid_map = std::to_string(uid) + " " + std::to_string(uid) + " 1\n";
  const std::string gid_map = std::to_string(gid) + " " + std::to_string(gid) + " 1\n";
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
    if (::unshare(uid == 0 ? CLONE_NEWNET : (CLONE_NEWUSER | CLONE_NEWNET)) != 0) fail(report[1], "unshare");
    if (uid != 0) {
      if (!write_file("/proc/self/setgroups", "deny") || !write_file("/proc/self/uid_map", uid_map.c_str()) ||
          !write_file("/proc/self/gid_map", gid_map.c_str())) {
        fail(report[1], "user namespace mapping");
      }
    }
    if (!configure_loopback()) fail(report[1], "loopback setup");
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

}  // namespace mtg::orchestrator
