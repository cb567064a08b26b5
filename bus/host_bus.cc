#include "bus/host_bus.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "bus/url.h"
#include "core/util/error.h"

namespace mtg::bus {

HostBusReservation::HostBusReservation() {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);  // held by this process only, not its children
  if (fd_ < 0) throw Error(std::string("cannot reserve a port for the host bus: socket: ") + std::strerror(errno));
  const int one = 1;
  const int zero = 0;
  ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  // This socket only holds the port: it must not take copies of the bus's datagrams.
  ::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_ALL, &zero, sizeof zero);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_ANY);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 ||
      ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd_);
    throw Error("cannot reserve a port for the host bus: " + why);
  }
  port_ = ntohs(addr.sin_port);
}

HostBusReservation::~HostBusReservation() {
  if (fd_ >= 0) ::close(fd_);
}

std::string HostBusReservation::url() const {
  const auto base = parse_udpm(kDefaultUrl);
  return normalize_url("udpm://" + base->group + ":" + std::to_string(port_) + "?ttl=0");
}

}  // namespace mtg::bus
