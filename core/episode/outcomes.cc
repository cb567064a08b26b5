#include "core/episode/outcomes.h"

#include <array>
#include <utility>

namespace mtg::episode {
namespace {

constexpr std::array<std::pair<EndReason, const char*>, 4> kEndReasons = {
    {{EndReason::kNone, ""}, {EndReason::kCallEnd, "call_end"}, {EndReason::kStepLimit, "step_limit"},
     {EndReason::kAborted, "aborted"}}};
constexpr std::array<std::pair<Stage, const char*>, 6> kStages = {
    {{Stage::kStart, "start"}, {Stage::kSource, "source"}, {Stage::kPicked, "picked"},
     {Stage::kDestination, "destination"}, {Stage::kPlaced, "placed"}, {Stage::kDone, "done"}}};
constexpr std::array<std::pair<Cause, const char*>, 14> kCauses = {
    {{Cause::kNone, ""}, {Cause::kProviderError, "provider_error"}, {Cause::kFormatError, "format_error"},
     {Cause::kInvalidActionLoop, "invalid_action_loop"}, {Cause::kNoCallEnd, "no_call_end"},
     {Cause::kOutcomeUnmet, "outcome_unmet"}, {Cause::kNavigation, "navigation"}, {Cause::kWrongItem, "wrong_item"},
     {Cause::kWrongRegion, "wrong_region"}, {Cause::kWrongPlatform, "wrong_platform"},
     {Cause::kStepLimit, "step_limit"}, {Cause::kEarlyEnd, "early_end"}, {Cause::kTransportError, "transport_error"},
     {Cause::kInfrastructure, "infrastructure"}}};

constexpr std::array<std::pair<Stage, const char*>, 6> kStageWords = {
    {{Stage::kStart, "did not reach the source platform"},
     {Stage::kSource, "reached the source platform, did not pick the item"},
     {Stage::kPicked, "picked the item, did not reach the destination"},
     {Stage::kDestination, "reached the destination, did not place the item as asked"},
     {Stage::kPlaced, "placed the item as asked, the task was not complete"},
     {Stage::kDone, "completed the task"}}};
constexpr std::array<std::pair<Cause, const char*>, 14> kCauseWords = {
    {{Cause::kNone, "success"},
     {Cause::kProviderError, "the model provider failed (the call returned an error)"},
     {Cause::kFormatError, "at least half of the replies named no offered action"},
     {Cause::kInvalidActionLoop, "ran out of steps after three or more invalid actions in a row"},
     {Cause::kNoCallEnd, "the goal was met but the agent never called the end (action 0)"},
     {Cause::kOutcomeUnmet, "ended, but the scene does not show the asked outcome"},
     {Cause::kNavigation, "never reached the platform the item stands on"},
     {Cause::kWrongItem, "picked up the wrong object"},
     {Cause::kWrongRegion, "placed the item on the right platform, in the wrong place"},
     {Cause::kWrongPlatform, "placed the item on another platform"},
     {Cause::kStepLimit, "ran out of steps"},
     {Cause::kEarlyEnd, "called the end (action 0) before the task was complete"},
     {Cause::kTransportError, "the judge missed a message (infrastructure; retried, not the agent's)"},
     {Cause::kInfrastructure, "the attempt was lost without a verdict (infrastructure; not the agent's)"}}};

template <class E, std::size_t N>
const char* name_of(const std::array<std::pair<E, const char*>, N>& table, E value) {
  for (const auto& [v, name] : table) {
    if (v == value) return name;
  }
  return "";
}

template <class E, std::size_t N>
std::optional<E> value_of(const std::array<std::pair<E, const char*>, N>& table, std::string_view name) {
  for (const auto& [v, n] : table) {
    if (name == n) return v;
  }
  return std::nullopt;
}

}  // namespace

const char* to_string(EndReason r) { return name_of(kEndReasons, r); }
const char* to_string(Stage s) { return name_of(kStages, s); }
const char* to_string(Cause c) { return name_of(kCauses, c); }
const char* explain(Stage s) { return name_of(kStageWords, s); }
const char* explain(Cause c) { return name_of(kCauseWords, c); }
std::string_view explain_stage(std::string_view name) {
  const auto s = stage_from_string(name);
  return s ? explain(*s) : name;
}
std::string_view explain_cause(std::string_view name) {
  const auto c = cause_from_string(name);
  return c ? explain(*c) : name;
}
std::optional<EndReason> end_reason_from_string(std::string_view name) { return value_of(kEndReasons, name); }
std::optional<Stage> stage_from_string(std::string_view name) { return value_of(kStages, name); }
std::optional<Cause> cause_from_string(std::string_view name) { return value_of(kCauses, name); }

}  // namespace mtg::episode
