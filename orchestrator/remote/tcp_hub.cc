#include "orchestrator/remote/tcp_hub.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include "bus/process/subprocess.h"
#include "bus/url.h"
#include "core/util/error.h"
#include "core/util/log.h"

namespace mtg::orchestrator::remote {
namespace {

namespace fs = std::filesystem;

std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return "";
}

}  // namespace

std::vector<std::string> hub_command(int port) {
  const char* jar_env = std::getenv("MTG_LCM_JAR");
  const std::string jar = jar_env != nullptr && *jar_env != '\0' ? jar_env : "/usr/share/java/lcm.jar";
  if (!fs::exists(jar)) throw Error("the LCM hub needs " + jar + " (Debian package liblcm-java, or set $MTG_LCM_JAR)");
  const std::string java = find_on_path("java");
  if (java.empty()) throw Error("the LCM hub needs java on the PATH (Debian package default-jre-headless)");
  return {java, "-Djava.net.preferIPv4Stack=true", "-cp", jar, "lcm.lcm.TCPService", std::to_string(port)};
}

namespace {

// Why a hub could not listen on `port` now; "" when it could.
std::string listen_error(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return std::strerror(errno);
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);  // as the hub's ServerSocket does
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_ANY);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  const bool ok = ::bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0 && ::listen(fd, 1) == 0;
  const std::string why = ok ? "" : std::strerror(errno);
  ::close(fd);
  return why;
}

}  // namespace

void check_hub_port(int port) {
  if (port < 1 || port > 65535) throw Error("hub port " + std::to_string(port) + " is not a TCP port (1..65535)");
  const std::string why = listen_error(port);
  if (!why.empty()) {
    throw Error("cannot listen on TCP port " + std::to_string(port) + " for the hub: " + why + " (another hub? use --hub-port)");
  }
}

namespace {

// Held from checking a hub's port until that hub listens, by every hub a run starts: two runs
// starting at once on one machine would otherwise both see the same port free, and the loser's
// probe would reach the winner's hub. One file for every user of the machine: it is opened
// read-only (all flock needs), and made world-readable by whoever creates it first.
class PortChoiceLock {
 public:
  // Not through a link (anyone may plant one in /tmp), only a regular file, and never waited on
  // for long: a process of another user holding it forever must not hang a run (issue 55).
  PortChoiceLock() {
    const char* path = "/tmp/mtg-hub-ports.lock";
    fd_ = ::open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
    if (fd_ < 0 && errno == ENOENT) {
      fd_ = ::open(path, O_RDONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
      if (fd_ >= 0) ::fchmod(fd_, 0644);
      if (fd_ < 0 && errno == EEXIST) fd_ = ::open(path, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);  // made meanwhile
    }
    struct stat st {};
    if (fd_ >= 0 && (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode))) {
      ::close(fd_);
      fd_ = -1;
      errno = EINVAL;
    }
    bool held = false;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(kWaitSeconds);
    while (fd_ >= 0 && !held) {
      held = ::flock(fd_, LOCK_EX | LOCK_NB) == 0;
      if (held || errno != EWOULDBLOCK || std::chrono::steady_clock::now() >= give_up) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!held) {
      log::warn(std::string("no lock on ") + path + " (" +
                (fd_ < 0 ? std::string(std::strerror(errno)) + "; a link or not a regular file is not used"
                         : "held by another process for " + std::to_string(kWaitSeconds) + " s") +
                "): a hub started at the same moment by another run could take the same port");
    }
  }
  ~PortChoiceLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  PortChoiceLock(const PortChoiceLock&) = delete;
  PortChoiceLock& operator=(const PortChoiceLock&) = delete;

 private:
  static constexpr int kWaitSeconds = 10;  // a hub starts listening within a few seconds
  int fd_ = -1;
};

int first_free_hub_port() {
  for (int port = kDefaultHubPort; port < kDefaultHubPort + kHubPortRange; ++port) {
    if (listen_error(port).empty()) return port;
  }
  throw Error("no free TCP port for the hub in " + std::to_string(kDefaultHubPort) + ".." +
              std::to_string(kDefaultHubPort + kHubPortRange - 1) + " (name one with --hub-port)");
}

}  // namespace

std::string hub_url(const std::string& host, int port) { return "tcpq://" + host + ":" + std::to_string(port); }

HubProcess::HubProcess(int port, const std::string& log_file) {
  const PortChoiceLock lock;
  port_ = port == kAnyPort ? first_free_hub_port() : port;
  check_hub_port(port_);
  pid_ = process::spawn_process(hub_command(port_), log_file, SIGTERM);
  const std::string hub = "the LCM hub on port " + std::to_string(port_);
  auto exited = [this] {
    int status = 0;
    return ::waitpid(pid_, &status, WNOHANG) == pid_;
  };
  // The JVM takes a fraction of a second to listen.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!bus::accepts_tcp("127.0.0.1", port_, std::chrono::milliseconds(500))) {
    if (exited()) {
      pid_ = -1;
      throw Error(hub + " exited at once; see " + log_file);
    }
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
      pid_ = -1;
      throw Error(hub + " did not listen within 20 s; see " + log_file);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // Something listens; if our JVM died meanwhile (it could not bind), that is another's hub.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (exited()) {
    pid_ = -1;
    throw Error(hub + " exited (is another program on that port?); see " + log_file);
  }
}

HubProcess::~HubProcess() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  int status = 0;
  ::waitpid(pid_, &status, 0);
}

}  // namespace mtg::orchestrator::remote
