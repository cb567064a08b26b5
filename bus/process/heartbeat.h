#pragma once
// The heartbeat every process publishes once a second on MTG_HEARTBEAT (liveness and capacity
// telemetry; never used in episode logic). Its status vocabulary is this enum; the message carries
// the name.

#include <optional>
#include <string>
#include <string_view>

#include "mtg/heartbeat_t.hpp"

namespace mtg::process {

enum class HeartbeatStatus {
  kStarting,  // a worker setting up a run's processes
  kIdle,      // a worker with no run
  kReady,     // can take work, holds none
  kBusy,      // holds work
  kDraining,  // stopping: takes nothing new
};

const char* to_string(HeartbeatStatus status);
/// nullopt for a name this build does not know (a newer peer).
std::optional<HeartbeatStatus> parse_heartbeat_status(std::string_view name);

struct HeartbeatFigures {
  std::string role;
  std::string host;
  int capacity = 0;
  int in_flight = 0;
  long tick = 0;
  HeartbeatStatus status = HeartbeatStatus::kReady;
};

/// The message for `figures` (header left to the caller); pid is this process's. A process that
/// is ready and holds work reports busy.
mtg::heartbeat_t heartbeat_message(const HeartbeatFigures& figures);

}  // namespace mtg::process
