#pragma once
// Level 4 feasibility votes: the paper lets several VLMs vote on whether an instantiated outcome
// task is executable. Voters are pluggable; until the VLM adapters vote live, the default voter
// is rule-based (a plan found with the episode rules), and votes recorded elsewhere (a JSONL file
// of {"task_id", "voter", "verdict"}) are merged in. A task is kept when a strict majority of its
// voters say "Feasible".

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

/// Reads recorded votes. @throws mtg::Error naming the file and line for bad lines or verdicts.
std::vector<Vote> load_votes(const std::string& jsonl_file);

/// Votes per task id.
std::map<std::string, std::vector<Vote>> group_votes(const std::vector<Vote>& votes);

/// Strict majority of "Feasible".
bool accepted(const std::vector<Vote>& votes);

}  // namespace mtg::tasks
