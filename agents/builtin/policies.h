#pragma once
// The built-in agents (no model, no API key):
//   oracle          follows the task's oracle plan (must score SR 100 %)
//   random          uniform over the offered keys, seeded by (episode seed, step)
//   replay:<run>    answers what a recorded run's agent answered (from its LCM logs)
//   script:<file>   replies from a JSON list {"replies": [...]} in step order (tests)

#include <memory>
#include <string>

#include "agents/common/policy.h"

namespace mtg::agents {

/// The agent that plays each task's oracle plan: the one agent given the episodes' answers.
inline constexpr const char* kOracleAgent = "oracle";

/// A person playing in the browser (agents/human, `mtg play`): its own process, not built in.
inline constexpr const char* kHumanAgent = "human";

/// Whether `spec` names one of the agents above (their files are not checked).
bool is_builtin_agent(const std::string& spec);

/// @throws mtg::Error for an unknown spec or an unreadable recording/script.
std::unique_ptr<Policy> make_builtin_policy(const std::string& spec);

}  // namespace mtg::agents
