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

// /proc of the calling thread: a namespace is per thread, and /proc/self is the main thread's.
std::string thread_proc(const std::string& rest) { return "/proc/self/task/" + std::to_string(::gettid()) + "/" + rest; }

constexpr const char* kUserNamespaceStep = "a user namespace";

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

// The two halves of enter_new_network: a user namespace is the whole process's, a network
// namespace the calling thread's. nullptr, or the step that failed with errno set.
const char* enter_new_user_namespace(const IdMaps& maps) noexcept {
  if (::unshare(CLONE_NEWUSER) != 0) return kUserNamespaceStep;
  if (!write_file("/proc/self/setgroups", "deny") || !write_file("/proc/self/uid_map", maps.uid_map.c_str()) ||
      !write_file("/proc/self/gid_map", maps.gid_map.c_str())) {
    return "the user namespace's id maps";
  }
  return nullptr;
}

const char* enter_new_network_namespace() noexcept {
  if (::unshare(CLONE_NEWNET) != 0) return "a network namespace";
  if (!configure_loopback()) return "loopback and its multicast route";
  return nullptr;
}

// Tries enter_new_network(maps) in a forked child: a process that moved into a user namespace
// cannot move back, so it moves only when the whole way is known to work.
// @throws mtg::Error naming the step that would fail.
void try_in_a_child(const IdMaps& maps) {
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) {
    const int error = errno;
    throw Error(failed("a pipe", error));
  }
  const pid_t child = ::fork();
  if (child < 0) {
    const int error = errno;
    ::close(report[0]);
    ::close(report[1]);
    throw Error(failed("fork", error));
  }
  if (child == 0) {  // only system calls: this process may have threads
    ::close(report[0]);
    if (const char* step = enter_new_network(&maps)) {
      const int error = errno;
      (void)!::write(report[1], &error, sizeof error);
      (void)!::write(report[1], step, std::strlen(step));
    }
    ::_exit(0);
  }
  ::close(report[1]);
  std::string said;
  char buf[128];
  for (;;) {
    const ssize_t n = ::read(report[0], buf, sizeof buf);
    if (n > 0) {
      said.append(buf, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(report[0]);
  while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
  }
  if (said.size() <= sizeof(int)) return;  // nothing failed
  int error = 0;
  std::memcpy(&error, said.data(), sizeof error);
  throw Error(failed(said.substr(sizeof error), error));
}

}  // namespace

IdMaps own_id_maps() {
  const std::string uid = std::to_string(::geteuid());
  const std::string gid = std::to_string(::getegid());
  return {uid + " " + uid + " 1\n", gid + " " + gid + " 1\n"};
}

const char* enter_new_network(const IdMaps* maps) noexcept {
  if (maps != nullptr) {
    if (const char* step = enter_new_user_namespace(*maps)) return step;
  }
  return enter_new_network_namespace();
}

std::shared_ptr<const PrivateNetwork> PrivateNetwork::make() {
  const bool user_namespace = ::geteuid() != 0;
  if (user_namespace) {
    // Only the owner of a user namespace may enter the network namespaces it owns, and only a
    // single-threaded process may move into a new user namespace.
    const IdMaps maps = own_id_maps();
    try_in_a_child(maps);
    if (const char* step = enter_new_user_namespace(maps)) {
      const int error = errno;
      const bool threads = step == kUserNamespaceStep && error == EINVAL;
      throw Error(failed(std::string(step) + (threads ? " (this process already runs threads)" : ""), error));
    }
  }
  int fd = -1;
  std::string why;
  // A thread of its own moves into the new namespace, opens it as a file and ends; the file
  // keeps the namespace alive.
  std::thread maker([&] {
    const std::string file = thread_proc("ns/net");
    if (const char* step = enter_new_network_namespace()) {
      const int error = errno;
      why = failed(step, error);
    } else if ((fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC)) < 0) {
      const int error = errno;
      why = failed(file, error);
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
