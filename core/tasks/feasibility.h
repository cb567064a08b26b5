#pragma once
// Level 4 feasibility votes: the paper lets several VLMs vote on whether an instantiated outcome
// task is executable. Every candidate has the rule-based vote (a plan found with the episode
// rules); live voters (model adapters, `mtg tasks --voter openai:gpt-4o`) vote on all candidates
// of a scene in one batch, and votes recorded elsewhere (a JSONL file of {"task_id", "voter",
// "verdict"}) are merged in. A task is kept when a strict majority of its voters say "Feasible".
// Every vote is stored in the task database.

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/tasks/task.h"

namespace mtg::tasks {

inline constexpr const char* kFeasible = "Feasible";
inline constexpr const char* kPartiallyFeasible = "Partially feasible";
inline constexpr const char* kNotFeasible = "Not feasible";

struct Vote {
  std::string task_id;
  std::string voter;    // "rules", "openai:gpt-4o", ...
  std::string verdict;  // one of the three constants above
};

/// What a live voter is asked about one candidate.
struct VoteRequest {
  std::string task_id;
  std::string scene;
  std::string text;               // the task as the agent would read it
  std::string scene_description;  // the platforms and what stands on them
  int step_limit = 15;
};

/// A live voter: one vote per request it could answer (it may skip some), in any order.
/// @throws mtg::Error when it cannot vote at all (nothing is written then).
using VoteBatch = std::function<std::vector<Vote>(const std::vector<VoteRequest>& requests)>;

/// Reads recorded votes. @throws mtg::Error naming the file and line for bad lines or verdicts.
std::vector<Vote> load_votes(const std::string& jsonl_file);

/// Votes per task id.
std::map<std::string, std::vector<Vote>> group_votes(const std::vector<Vote>& votes);

/// Strict majority of "Feasible".
bool accepted(const std::vector<Vote>& votes);

}  // namespace mtg::tasks
