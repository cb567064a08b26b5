#include "bus/bus.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <utility>

#include "bus/header.h"
#include "bus/url.h"
#include "core/util/log.h"

namespace mtg::bus {

Bus::Bus(const std::string& url, std::shared_ptr<const PrivateNetwork> network) : url_(normalize_url(url)) {
  if (network == nullptr) {
    connect();
    return;
  }
  network->run_inside([this] {
    connect();
    if (udpm_port_ == 0) return;
    // liblcm opens its receive socket at the first subscription, in the thread that makes it:
    // that must happen in here, not in whichever thread subscribes first.
    lcm::Subscription* opener = lcm_->subscribeFunction(
        "MTG_PRIVATE_NETWORK_OPEN", +[](const lcm::ReceiveBuffer*, const std::string&, void*) {}, static_cast<void*>(nullptr));
    lcm_->unsubscribe(opener);
    // liblcm's C++ wrapper returns a subscription even when the receive side failed to start, and
    // would then try again from the next subscriber's thread, outside: so the socket is checked.
    const std::vector<OpenSocket> opened = sockets_opened();
    if (opened.size() != 1) {
      throw Error("LCM did not open its receive socket on " + url_ + " inside the host bus's network namespace (" +
                  std::to_string(opened.size()) + " new sockets on its port)");
    }
    receive_socket_ = opened.front();
  });
}

void Bus::connect() {
  check_multicast_route(url_);
  // A hub started at the same moment (a script, a Slurm array) gets a few seconds to listen.
  check_hub_reachable(url_, std::chrono::seconds(10));
  is_log_ = url_.rfind("file://", 0) == 0;
  if (const auto udpm = parse_udpm(url_)) sockets_before_ = udp_sockets_on_port(udpm->port);
  lcm_ = std::make_unique<lcm::LCM>(url_);
  if (!lcm_->good()) {
    throw Error("cannot start LCM on " + url_ +
                " (for udpm: is the multicast route set? `ip route replace 224.0.0.0/4 dev lo`)");
  }
  tcp_ = parse_tcpq(url_).has_value();
  if (tcp_) tune_tcp();
  if (const auto udpm = parse_udpm(url_)) {
    udpm_port_ = udpm->port;
    // ttl=0: every message of this bus is looped back on this host; nothing else is let in.
    channels_ = ChannelFilter(loopback_group_of(url_));
  }
}

void Bus::subscribe_raw(const std::string& channel_regex, RawHandler::Fn handler) {
  auto owned = std::make_unique<RawHandler>(std::move(handler), pending_, auth_);
  lcm::Subscription* sub = lcm_->subscribe(channel_regex, &RawHandler::on, owned.get());
  if (sub == nullptr) throw Error("LCM subscribe failed for " + channel_regex);
  sub->setQueueCapacity(kQueueCapacity);
  handlers_.push_back(std::move(owned));
  filter_channels(channel_regex);
}

std::vector<OpenSocket> Bus::sockets_opened() const {
  std::vector<OpenSocket> opened;
  for (const OpenSocket& s : udp_sockets_on_port(udpm_port_)) {
    if (std::find(sockets_before_.begin(), sockets_before_.end(), s) == sockets_before_.end()) opened.push_back(s);
  }
  return opened;
}

void Bus::filter_channels(const std::string& subscription) {
  if (udpm_port_ == 0 || !channels_.add(subscription)) return;
  // Every way this can fail leaves the bus unfiltered: slower, never deaf to a subscription.
  auto give_up = [&](const std::string& why) {
    if (receive_socket_.fd >= 0 && is_open_socket(receive_socket_, udpm_port_)) {
      detach_socket_filter(receive_socket_.fd);
    }
    udpm_port_ = 0;
    filtered_ = false;
    log::warn("LCM on " + url_ + ": " + why + "; every message on the bus wakes this process");
  };
  if (receive_socket_.fd < 0) {
    const std::vector<OpenSocket> opened = sockets_opened();
    if (opened.size() != 1) {  // e.g. another bus of this process opened one too: leave both alone
      udpm_port_ = 0;
      if (channels_.host_only()) {
        log::warn("LCM on " + url_ + ": its receive socket was not told apart from another (" +
                  std::to_string(opened.size()) + " candidates), so datagrams sent to this port from another " +
                  "machine reach this process; give each bus of a process a port of its own");
        return;
      }
      log::debug("LCM receive socket on " + url_ + " not told apart (" + std::to_string(opened.size()) +
                 " candidates): every message wakes this process");
      return;
    }
    receive_socket_ = opened.front();
  } else if (!is_open_socket(receive_socket_, udpm_port_)) {
    // liblcm keeps its socket for the bus's life; had it replaced it, the descriptor could name
    // another socket by now, which must never get this filter (the old one went with its socket).
    receive_socket_ = {};
    give_up("the receive socket was replaced");
    return;
  }
  try {
    if (const auto program = channels_.program()) {
      attach_socket_filter(receive_socket_.fd, *program);
      filtered_ = !channels_.everything();
    } else {
      detach_socket_filter(receive_socket_.fd);
      filtered_ = false;
    }
  } catch (const Error& e) {
    give_up(e.what());
  }
}

bool Bus::SchemaGate::admit_header(const mtg::header_t& header, const std::string& channel) {
  if (speaks_our_schema(header)) return true;
  ++dropped;
  if (!std::exchange(warned, true)) log::warn(schema_mismatch(header, "message on " + channel) + "; dropped");
  return false;
}

std::string Bus::hub_lost(const std::string& doing) const {
  return "lost the LCM hub at " + url_ + " (it stopped, or the network to it failed)" + doing +
         "; start it again (`mtg hub`) and run the same command to resume";
}

void Bus::publish_failed(const std::string& channel) const {
  if (tcp_) throw Error(hub_lost(" while publishing on " + channel));
  throw Error("LCM publish failed on channel " + channel + " (" + url_ + ")");
}

void Bus::rethrow_pending() {
  if (!pending_) return;
  std::exception_ptr e = std::exchange(pending_, nullptr);
  std::rethrow_exception(e);
}

// LCM's hub (TCPService) writes each message in five small unbuffered writes with Nagle on, so
// every write after the first waited for our delayed ACK: up to 40 ms per message, which made a
// hub run 3.5x slower than multicast. Linux leaves quick-ACK mode by itself, so it is re-armed
// before every receive. Nagle goes off on our side too (liblcm leaves it on), set here rather
// than once because liblcm opens a new socket when it reconnects.
void Bus::tune_tcp() {
  const int on = 1;
  const int fd = lcm_->getFileno();
  ::setsockopt(fd, IPPROTO_TCP, TCP_QUICKACK, &on, sizeof on);
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof on);
}

bool Bus::handle_once(int timeout_ms) {
  if (is_log_) {
    // The file provider hands out one event per handle(); it returns non-zero at the end.
    if (end_of_log_) return false;
    if (lcm_->handle() != 0) {
      end_of_log_ = true;
      return false;
    }
    rethrow_pending();
    return true;
  }
  if (tcp_) tune_tcp();
  const int rc = lcm_->handleTimeout(timeout_ms);
  rethrow_pending();
  // A signal (SIGINT, SIGTERM: the caller's stop request) interrupts the wait: nothing handled.
  if (rc < 0 && errno == EINTR) return false;
  if (rc < 0 && tcp_) {
    // liblcm closes its socket when the hub goes and fails to reconnect; its errno is then that
    // of the closed descriptor ("Bad file descriptor"), which names nothing the user can fix.
    throw Error(hub_lost(""));
  }
  if (rc < 0) throw Error("LCM handle failed on " + url_ + ": " + std::strerror(errno));
  return rc > 0;
}

bool Bus::handle_until(const std::function<bool()>& done, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (!done()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                          deadline - std::chrono::steady_clock::now())
                          .count();
    if (left <= 0) break;
    if (!handle_once(static_cast<int>(std::min<long>(left, 50))) && is_log_ && end_of_log_) break;
  }
  return done();
}

void Bus::log_unopened(const std::string& why) {
  log::warn(why + "; dropped (this warning once per bus, Bus::unopened() counts them)");
}

}  // namespace mtg::bus
