#include "services/common/service_loop.h"

#include <unistd.h>

#include <chrono>
#include <csignal>

#include "bus/channels.h"
#include "core/util/log.h"
#include "mtg/heartbeat_t.hpp"
#include "mtg/run_control_t.hpp"

namespace mtg::services {
namespace {

// Signal handlers can only touch a lock-free flag; this is the one process-wide state.
volatile std::sig_atomic_t g_stop_signal = 0;

void on_signal(int) { g_stop_signal = 1; }

}  // namespace

std::string host_name() {
  char buf[256] = {0};
  if (gethostname(buf, sizeof(buf) - 1) != 0) return "unknown";
  return buf;
}

void install_stop_signals() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

std::string sender_id(const std::string& role) {
  return role + ":" + host_name() + ":" + std::to_string(::getpid());
}

ServiceLoop::ServiceLoop(bus::Bus& bus, bus::HeaderStamper& stamp, std::string role, int capacity,
                         bool obeys_shutdown)
    : bus_(bus), stamp_(stamp), role_(std::move(role)), capacity_(capacity) {
  if (!obeys_shutdown) return;
  bus_.subscribe<mtg::run_control_t>(bus::kControl, [this](const std::string&, const mtg::run_control_t& m) {
    // A process of a run obeys its own run only: another run's shutdown is not ours.
    const bool my_run = stamp_.run_id().empty() || m.header.run_id == stamp_.run_id();
    const bool for_me = my_run && (m.target.empty() || m.target == role_ || m.target == stamp_.sender());
    if (for_me && m.command == "shutdown") {
      log::info("shutdown requested by " + m.header.sender);
      stopping_ = true;
    }
  });
}

bool stop_signal_received() { return g_stop_signal != 0; }

bool ServiceLoop::stopping() const { return stopping_ || stop_signal_received(); }

void ServiceLoop::heartbeat() {
  mtg::heartbeat_t hb{};
  hb.header = stamp_.next(-1, 0, "heartbeat");
  hb.role = role_;
  hb.host = host_name();
  hb.pid = static_cast<int32_t>(::getpid());
  hb.capacity = capacity_;
  hb.in_flight = in_flight_;
  hb.tick = tick_++;
  hb.status = stopping() ? "draining" : (in_flight_ > 0 ? "busy" : "ready");
  bus_.publish(bus::kHeartbeat, hb);
}

void ServiceLoop::run(const std::function<void()>& idle) {
  auto next_beat = std::chrono::steady_clock::now();
  while (!stopping()) {
    if (std::chrono::steady_clock::now() >= next_beat) {
      heartbeat();
      next_beat += std::chrono::seconds(1);
    }
    // Drain whatever is queued, then let the service work.
    while (bus_.handle_once(0) && !stopping()) {
    }
    if (idle) idle();
    bus_.handle_once(20);
  }
  heartbeat();  // a last "draining" beat
}

}  // namespace mtg::services
