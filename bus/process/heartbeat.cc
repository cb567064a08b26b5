#include "bus/process/heartbeat.h"

#include <unistd.h>

#include <array>
#include <utility>

namespace mtg::process {
namespace {

constexpr std::array<std::pair<HeartbeatStatus, const char*>, 5> kNames{{
    {HeartbeatStatus::kStarting, "starting"},
    {HeartbeatStatus::kIdle, "idle"},
    {HeartbeatStatus::kReady, "ready"},
    {HeartbeatStatus::kBusy, "busy"},
    {HeartbeatStatus::kDraining, "draining"},
}};

}  // namespace

const char* to_string(HeartbeatStatus status) {
  for (const auto& [s, name] : kNames) {
    if (s == status) return name;
  }
  return "ready";
}

std::optional<HeartbeatStatus> parse_heartbeat_status(std::string_view name) {
  for (const auto& [s, n] : kNames) {
    if (name == n) return s;
  }
  return std::nullopt;
}

mtg::heartbeat_t heartbeat_message(const HeartbeatFigures& f) {
  mtg::heartbeat_t hb{};
  hb.role = f.role;
  hb.host = f.host;
  hb.pid = static_cast<int32_t>(::getpid());
  hb.capacity = f.capacity;
  hb.in_flight = f.in_flight;
  hb.tick = f.tick;
  const bool busy = f.status == HeartbeatStatus::kReady && f.in_flight > 0;
  hb.status = to_string(busy ? HeartbeatStatus::kBusy : f.status);
  return hb;
}

}  // namespace mtg::process
