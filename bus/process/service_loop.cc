#include "bus/process/service_loop.h"

#include <chrono>

#include "bus/channels.h"
#include "bus/process/heartbeat.h"
#include "core/util/log.h"
#include "mtg/run_control_t.hpp"

namespace mtg::process {

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

bool ServiceLoop::stopping() const { return stopping_ || stop_signal_received(); }

void ServiceLoop::heartbeat() {
  const HeartbeatStatus status = stopping() ? HeartbeatStatus::kDraining : HeartbeatStatus::kReady;
  mtg::heartbeat_t hb = heartbeat_message({role_, host_name(), capacity_, in_flight_, tick_++, status});
  hb.header = stamp_.next({}, 0, "heartbeat");
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

}  // namespace mtg::process
