#include "bus/error_events.h"

#include <string_view>
#include <utility>

namespace mtg::bus {
namespace {

constexpr std::string_view kAgentPrefix = "agent:";

}  // namespace

const char* to_string(Severity severity) {
  switch (severity) {
    case Severity::kWarning: return "warning";
    case Severity::kFailure: return "error";
    case Severity::kFatal: return "fatal";
  }
  return "error";
}

mtg::error_event_t error_event(std::string source, Severity severity, std::string message) {
  mtg::error_event_t m{};
  m.source = std::move(source);
  m.severity = to_string(severity);
  m.message = std::move(message);
  return m;
}

std::string agent_role(const std::string& spec) { return std::string(kAgentPrefix) + spec; }

mtg::error_event_t agent_stopped_event(const std::string& spec, std::string why) {
  return error_event(agent_role(spec), Severity::kFatal, std::move(why));
}

std::optional<std::string> stopped_agent(const mtg::error_event_t& event) {
  if (event.severity != to_string(Severity::kFatal) || !event.source.starts_with(kAgentPrefix)) return std::nullopt;
  return event.source.substr(kAgentPrefix.size());
}

}  // namespace mtg::bus
