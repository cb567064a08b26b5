#pragma once
// A network namespace of a process's own for the bus of its run's processes (docs/multihost.md,
// "A worker's own bus"). `mtg run` re-executes itself inside one (orchestrator/run/run_namespace.h);
// `mtg worker` cannot, since it must stay on the shared bus between hosts, so it keeps a
// namespace beside its own: its host-bus sockets are made inside it (a socket belongs to the
// namespace of the thread that made it, for good) and its run's processes enter it before they
// execute. Nothing outside -- another host, another process of this host, another worker -- can
// then send to that bus or hear it.
//
// As root the namespace is a network namespace alone. Otherwise the process first becomes the
// owner of a user namespace of its own that maps its uid and gid to themselves (Debian 12 allows
// it unprivileged), which is possible only while it is single-threaded: make it at start.

#include <functional>
#include <memory>
#include <string>

namespace mtg::bus {

class PrivateNetwork {
 public:
  /// A new network namespace with loopback up and 224.0.0.0/4 routed through it.
  /// @throws mtg::Error naming the step that failed (namespaces forbidden by the kernel or a
  /// container, a process already multi-threaded when not root, ...).
  static std::shared_ptr<const PrivateNetwork> make();
  ~PrivateNetwork();
  PrivateNetwork(const PrivateNetwork&) = delete;
  PrivateNetwork& operator=(const PrivateNetwork&) = delete;

  /// Runs `fn` on a thread inside the namespace and waits for it; what it throws is rethrown.
  /// Sockets it makes stay in the namespace; the calling thread never leaves its own.
  void run_inside(const std::function<void()>& fn) const;
  /// Enters the namespace; for a child between fork and exec (async-signal-safe). False on failure.
  bool enter() const noexcept;

  /// The namespace as a file another tool can enter while this process lives
  /// (`nsenter --net=PATH`), e.g. /proc/<pid>/fd/<n>.
  std::string path() const;
  /// Whether this process made a user namespace for it (when not root): a tool entering the
  /// namespace enters /proc/<pid>/ns/user first.
  bool in_user_namespace() const { return user_namespace_; }

 private:
  PrivateNetwork(int fd, bool user_namespace) : fd_(fd), user_namespace_(user_namespace) {}
  int fd_ = -1;
  bool user_namespace_ = false;
};

/// Brings loopback up and routes 224.0.0.0/4 through it, in the calling thread's network
/// namespace (async-signal-safe). False on failure, errno set.
bool configure_loopback() noexcept;

/// Maps this process, just moved into a new user namespace, to its own uid and gid (the texts
/// "<id> <id> 1\n", prepared before a fork). Async-signal-safe. False on failure, errno set.
bool map_user_namespace(const char* uid_map, const char* gid_map) noexcept;

}  // namespace mtg::bus
