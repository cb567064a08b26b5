#pragma once
// A run's own network namespace (docs/runtime.md, "Isolation"). The processes of a run on this
// machine share a bus that nothing outside the run can reach or disturb: another run, another
// user, a datagram from another host. `mtg run` executes itself again in a new network namespace
// (inside a new user namespace when not root, which Debian 12 allows unprivileged) with loopback
// up and multicast routed through it, so the bus needs no root and no `scripts/with-bus`. The
// outer process stays outside: it relays the model adapters' HTTP (agents/vlm/http_relay.h),
// passes SIGINT/SIGTERM on, and exits with the inner run's status.
//
// Where namespaces are not available (a kernel or container that forbids them) the run goes on
// on the host's loopback group after one line saying so; its processes still ignore every
// message of another run (run ids are unique), but a datagram sent to this host from elsewhere
// could reach it.

#include <filesystem>
#include <optional>
#include <string>

#include "bus/private_network.h"

namespace mtg::orchestrator {

class PageRelay;

/// Set in the environment of a run inside its own namespace.
inline constexpr const char* kRunNamespaceEnv = "MTG_RUN_NAMESPACE";

/// Whether this process runs inside a run's own namespace.
bool inside_run_namespace();

/// Runs `argv` (this program's own command line) again in a new network namespace and returns
/// its exit status, unless this process is inside one already (nullopt: go on here) or no
/// namespace can be made (nullopt, after a one-line notice naming why).
/// With `page`, the inner run serves the play page on its socket and `page` relays the page's TCP
/// address to it (page_relay.h) while the run lasts.
std::optional<int> run_in_own_namespace(char** argv, PageRelay* page = nullptr);

/// `<dir>/bus.json`, for `scripts/lcm-spy --run DIR`: the bus's URL and the namespace that holds
/// it, `network` (a worker's, bus/private_network.h) or else this process's own, which is a run's
/// own namespace when inside_run_namespace().
void write_bus_file(const std::filesystem::path& dir, const std::string& url,
                    const bus::PrivateNetwork* network = nullptr);

}  // namespace mtg::orchestrator
