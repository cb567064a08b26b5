#pragma once
// The words an episode ends with, as types (one name table each): why it ended, how far the
// agent got (the Sankey's stages, in flow order), and why it failed (docs/episode.md). Messages
// and databases carry the names; code compares the enums.

#include <optional>
#include <string_view>

namespace mtg::episode {

/// Why an episode ended: the agent's call_end, the step limit, or a provider failure.
enum class EndReason { kNone, kCallEnd, kStepLimit, kAborted };

/// The furthest milestone of the first part not completed, in flow order; kDone on success.
enum class Stage { kStart, kSource, kPicked, kDestination, kPlaced, kDone };

/// Why an episode failed (kNone on success). kTransportError (the judge missed a message) and
/// kInfrastructure (an attempt lost without a verdict) are never the agent's: the orchestrator
/// retries such attempts, and gives up on them with status "error".
enum class Cause {
  kNone, kProviderError, kFormatError, kInvalidActionLoop, kNoCallEnd, kOutcomeUnmet, kNavigation,
  kWrongItem, kWrongRegion, kWrongPlatform, kStepLimit, kEarlyEnd, kTransportError, kInfrastructure,
};

/// "", "call_end", "step_limit", "aborted".
const char* to_string(EndReason r);
/// "start", "source", "picked", "destination", "placed", "done".
const char* to_string(Stage s);
/// "", "provider_error", "format_error", ... (docs/episode.md).
const char* to_string(Cause c);

/// The same in plain words for people reading a report or the viewer, e.g. "picked up the wrong
/// object". Stages say how far the agent got: "reached the source platform".
const char* explain(Stage s);
const char* explain(Cause c);
/// The same for a stored name; the name itself when it is none of ours (a newer writer's).
std::string_view explain_stage(std::string_view name);
std::string_view explain_cause(std::string_view name);

/// The enum with that name, or nullopt.
std::optional<EndReason> end_reason_from_string(std::string_view name);
std::optional<Stage> stage_from_string(std::string_view name);
std::optional<Cause> cause_from_string(std::string_view name);

/// Causes the run tries again rather than scoring: a lost message or a failing model API is
/// never the agent's failure (the run engine and the play desk both ask this).
constexpr bool is_retried(Cause c) { return c == Cause::kTransportError || c == Cause::kProviderError; }

inline constexpr Stage kStagesInOrder[] = {Stage::kStart, Stage::kSource, Stage::kPicked,
                                           Stage::kDestination, Stage::kPlaced, Stage::kDone};

}  // namespace mtg::episode
