#pragma once
// A bus of this host alone for one `mtg worker`: the loopback group (ttl=0) on a UDP port that
// no other bus on this host uses. Two workers on one machine -- a Slurm node running two array
// tasks of a job, or two of a user's jobs -- would otherwise share one group and port and hear
// each other's episodes.

#include <string>

namespace mtg::bus {

class HostBusReservation {
 public:
  /// Asks the kernel for a free UDP port and keeps a socket bound to it (SO_REUSEADDR, so LCM can
  /// bind the same port) for as long as this object lives: no later port-0 bind on this host is
  /// given that port. @throws mtg::Error when no socket can be bound.
  HostBusReservation();
  ~HostBusReservation();
  HostBusReservation(const HostBusReservation&) = delete;
  HostBusReservation& operator=(const HostBusReservation&) = delete;

  int port() const { return port_; }
  /// The loopback group of kDefaultUrl on the reserved port, normalised.
  std::string url() const;

 private:
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace mtg::bus
