#pragma once
// A network namespace of a process's own for the bus of its run's processes (docs/multihost.md,
// "A worker's own bus"). `mtg run` re-executes itself inside one (orchestrator/run/run_namespace.h);
// `mtg worker` cannot, since it must stay on the shared bus between hosts, so it keeps a
// namespace beside its own: its host-bus sockets are made inside it (a socket belongs to the
// namespace of the thread that made it, for good) and its run's processes enter it before they
// execute. Nothing outside -- another host, another worker, a process of this host that does not
// enter the namespace on purpose (which takes this process's uid, or root) -- can then send to
// that bus or hear it.
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

/// A user namespace's maps of this process's uid and gid to themselves ("<id> <id> 1\n" each),
/// made before a fork so the child needs no allocation.
struct IdMaps {
  std::string uid_map;
  std::string gid_map;
};
IdMaps own_id_maps();

/// Moves the calling process into a new network namespace with loopback up and 224.0.0.0/4
/// routed through it; with `maps` (not root) into a new user namespace so mapped first. Only
/// system calls, for a child between fork and exec (`mtg run`'s own namespace, run_namespace.h).
/// nullptr on success, else the step that failed ("a user namespace", ...), errno set.
const char* enter_new_network(const IdMaps* maps) noexcept;

}  // namespace mtg::bus
