#pragma once
// The loop every service process runs: dispatch bus messages, publish a heartbeat once a
// second (liveness telemetry, never used in episode logic), stop on SIGINT/SIGTERM or on a
// run_control "shutdown" of its own run addressed to this role, and give the service a chance to do queued
// work between messages (handlers stay short; heavy work runs from `idle`).

#include <functional>
#include <string>

#include "bus/bus.h"
#include "bus/header.h"
#include "bus/process/identity.h"
#include "bus/process/stop_signals.h"

namespace mtg::process {

class ServiceLoop {
 public:
  /// `obeys_shutdown` false: only a signal stops the loop, not a run_control "shutdown" (the
  /// recorder keeps recording while the other services stop).
  ServiceLoop(bus::Bus& bus, bus::HeaderStamper& stamp, std::string role, int capacity = 1,
              bool obeys_shutdown = true);

  /// Runs until stopped. `idle` is called after each round of message handling.
  void run(const std::function<void()>& idle = {});
  void stop() { stopping_ = true; }
  bool stopping() const;
  /// Episodes (or jobs) currently held, reported in heartbeats.
  void set_in_flight(int n) { in_flight_ = n; }

 private:
  void heartbeat();

  bus::Bus& bus_;
  bus::HeaderStamper& stamp_;
  std::string role_;
  int capacity_;
  int in_flight_ = 0;
  long tick_ = 0;
  bool stopping_ = false;
};

}  // namespace mtg::process
