#include "bus/private_network.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <net/if.h>
#include <net/route.h>
#include <netinet/in.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <thread>

#include "core/util/error.h"

namespace mtg::bus {
namespace {

bool write_file(const char* path, const char* text) noexcept {
  const int fd = ::open(path, O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const auto n = static_cast<ssize_t>(std::strlen(text));
  const bool ok = ::write(fd, text, static_cast<std::size_t>(n)) == n;
  const int saved = errno;
  ::close(fd);
  errno = saved;
  return ok;
}

std::string failed(const std::string& what, int error) {
  std::string why = what + ": " + std::strerror(error);
  if (error == ENOSPC) why += " (the limit of namespaces, sysctl user.max_user_namespaces or user.max_net_namespaces)";
  if (error == EPERM) why += " (not permitted here: a container, a security module or a sysctl forbids it)";
  return "cannot make a network namespace for the host bus: " + why;
}
std::string failed(const std::string& what) { return failed(what, errno); }

// /proc of the calling thread: a namespace is per thread, and /proc/self is the main thread's.
std::string thread_proc(const std::string& rest) { return "/proc/self/task/" + std::to_string(::gettid()) + "/" + rest; }

// Steps of a namespace made without root, tried by a forked child first: a process that moved
// into a user namespace cannot move back, so it moves only when the whole way is known to work.
enum class Step : int { kNone, kUserNamespace, kIdMaps, kNetworkNamespace, kLoopback };

const char* step_name(Step step) {
  switch (step) {
    case Step::kUserNamespace: return "a user namespace";
    case Step::kIdMaps: return "the user namespace's id maps";
    case Step::kNetworkNamespace: return "unshare";
    case Step::kLoopback: return "loopback and its multicast route";
    case Step::kNone: break;
  }
  return "";
}

// In the child: only system calls (this may run in a process that has threads).
Step try_unprivileged(const char* uid_map, const char* gid_map) noexcept {
  if (::unshare(CLONE_NEWUSER) != 0) return Step::kUserNamespace;
  if (!map_user_namespace(uid_map, gid_map)) return Step::kIdMaps;
  if (::unshare(CLONE_NEWNET) != 0) return Step::kNetworkNamespace;
  if (!configure_loopback()) return Step::kLoopback;
  return Step::kNone;
}

// @throws mtg::Error naming the step that would fail.
void probe_unprivileged(const std::string& uid_map, const std::string& gid_map) {
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) throw Error(failed("a pipe"));
  const pid_t child = ::fork();
  if (child < 0) {
    const int error = errno;
    ::close(report[0]);
    ::close(report[1]);
    throw Error(failed("fork", error));
  }
  if (child == 0) {
    ::close(report[0]);
    const int out[2] = {static_cast<int>(try_unprivileged(uid_map.c_str(), gid_map.c_str())), errno};
    (void)!::write(report[1], out, sizeof out);
    ::_exit(0);
  }
  ::close(report[1]);
  int in[2] = {static_cast<int>(Step::kNone), 0};
  ssize_t n;
  do {
    n = ::read(report[0], in, sizeof in);
  } while (n < 0 && errno == EINTR);
  ::close(report[0]);
  while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
  }
  if (n != static_cast<ssize_t>(sizeof in)) throw Error(failed("a trial in a child process", EIO));
  if (static_cast<Step>(in[0]) != Step::kNone) throw Error(failed(step_name(static_cast<Step>(in[0])), in[1]));
}

}  // namespace

bool configure_loopback() noexcept {
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
  const int saved = errno;
  ::close(fd);
  errno = saved;
  return ok;
}

bool map_user_namespace(const char* uid_map, const char* gid_map) noexcept {
  return write_file("/proc/self/setgroups", "deny") && write_file("/proc/self/uid_map", uid_map) &&
         write_file("/proc/self/gid_map", gid_map);
}

std::shared_ptr<const PrivateNetwork> PrivateNetwork::make() {
  const uid_t uid = ::geteuid();
  bool user_namespace = false;
  if (uid != 0) {
    // Only the owner of a user namespace may enter the network namespaces it owns, and only a
    // single-threaded process may move into a new user namespace.
    const std::string uid_map = std::to_string(uid) + " " + std::to_string(uid) + " 1\n";
    const std::string gid_map = std::to_string(::getegid()) + " " + std::to_string(::getegid()) + " 1\n";
    probe_unprivileged(uid_map, gid_map);
    if (::unshare(CLONE_NEWUSER) != 0) {
      throw Error(failed(errno == EINVAL ? "a user namespace (this process already runs threads)" : "a user namespace"));
    }
    if (!map_user_namespace(uid_map.c_str(), gid_map.c_str())) throw Error(failed("the user namespace's id maps"));
    user_namespace = true;
  }
  int fd = -1;
  std::string why;
  // A thread of its own moves into the new namespace, opens it as a file and ends; the file
  // keeps the namespace alive.
  std::thread maker([&] {
    if (::unshare(CLONE_NEWNET) != 0) {
      why = failed("unshare");
    } else if (!configure_loopback()) {
      why = failed("loopback and its multicast route");
    } else if ((fd = ::open(thread_proc("ns/net").c_str(), O_RDONLY | O_CLOEXEC)) < 0) {
      why = failed(thread_proc("ns/net"));
    }
  });
  maker.join();
  if (fd < 0) throw Error(why);
  return std::shared_ptr<const PrivateNetwork>(new PrivateNetwork(fd, user_namespace));
}

PrivateNetwork::~PrivateNetwork() {
  if (fd_ >= 0) ::close(fd_);
}

bool PrivateNetwork::enter() const noexcept { return ::setns(fd_, CLONE_NEWNET) == 0; }

void PrivateNetwork::run_inside(const std::function<void()>& fn) const {
  std::exception_ptr thrown;
  std::thread inside([&] {
    try {
      if (!enter()) throw Error(std::string("cannot enter the host bus's network namespace: ") + std::strerror(errno));
      fn();
    } catch (...) {
      thrown = std::current_exception();
    }
  });
  inside.join();
  if (thrown) std::rethrow_exception(thrown);
}

std::string PrivateNetwork::path() const { return "/proc/" + std::to_string(::getpid()) + "/fd/" + std::to_string(fd_); }

}  // namespace mtg::bus
