#pragma once
// What travels on MTG_ERROR, as types: how bad it is, and the one event that changes a run (an
// agent that will take no more episodes, e.g. its provider refused the key). Everything else on
// the channel is a report for people and logs.

#include <optional>
#include <string>

#include "mtg/error_event_t.hpp"

namespace mtg::bus {

enum class Severity {
  kWarning,  // survived, nothing lost
  kFailure,  // one request or episode failed ("error" on the wire)
  kFatal,    // the source stops taking work
};

const char* to_string(Severity severity);

/// An error event from `source` (header left to the caller).
mtg::error_event_t error_event(std::string source, Severity severity, std::string message);

/// The process role of the agent `spec` ("agent:<spec>"): its heartbeats and its stop event.
std::string agent_role(const std::string& spec);

/// Agent `spec` stops taking episodes because of `why`, said once (header left to the caller).
mtg::error_event_t agent_stopped_event(const std::string& spec, std::string why);
/// The agent's spec when `event` says an agent stopped; nullopt for every other event.
std::optional<std::string> stopped_agent(const mtg::error_event_t& event);

}  // namespace mtg::bus
