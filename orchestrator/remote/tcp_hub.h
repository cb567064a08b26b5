#pragma once
// The shared bus where hosts have no multicast between them: LCM's own TCP hub (the stock
// `lcm.lcm.TCPService` of lcm.jar), which every participant reaches with a `tcpq://host:port`
// URL. The hub relays each message to the clients subscribed to its channel (docs/multihost.md,
// "Without multicast").

#include <sys/types.h>

#include <string>
#include <vector>

namespace mtg::orchestrator::remote {

inline constexpr int kDefaultHubPort = 7700;
inline constexpr int kHubPortRange = 100;  // a run's own hub takes the first free port from the default

/// The java command line of the stock hub on `port`. lcm.jar is $MTG_LCM_JAR, else Debian's
/// /usr/share/java/lcm.jar (package liblcm-java). @throws mtg::Error naming what is missing.
std::vector<std::string> hub_command(int port);

/// @throws mtg::Error when `port` cannot be listened on (taken, or privileged), before the hub
/// would fail with a Java stack trace.
void check_hub_port(int port);

/// The URL that reaches a hub on `host`:`port`.
std::string hub_url(const std::string& host, int port);

/// A hub started for one run (`mtg run --slurm` without --bus): stopped when this object goes,
/// and by the kernel if this process dies.
class HubProcess {
 public:
  static constexpr int kAnyPort = 0;
  /// Starts the hub on `port` (kAnyPort: the first free one from kDefaultHubPort) and waits
  /// until it accepts connections. The port is checked and taken under a machine-wide lock, so
  /// two runs starting at once get two hubs. @throws mtg::Error.
  HubProcess(int port, const std::string& log_file);
  ~HubProcess();
  HubProcess(const HubProcess&) = delete;
  HubProcess& operator=(const HubProcess&) = delete;

  pid_t pid() const { return pid_; }
  int port() const { return port_; }

 private:
  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace mtg::orchestrator::remote
