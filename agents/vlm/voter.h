#pragma once
// Level 4 feasibility voting through a model (`mtg tasks --voter <agent spec>`): the vote
// template (prompts/<version>/vote.txt) asks whether the task can be done in this apartment;
// the answer is read as Feasible, Partially feasible or Not feasible. Candidates are voted on in
// parallel through one ModelClient (cache, retries and rate gate included), so a rerun of the
// same generation costs no API call and gives the same votes.

#include <string>
#include <string_view>
#include <vector>

#include "agents/vlm/model_client.h"
#include "agents/vlm/prompt.h"
#include "core/tasks/feasibility.h"

namespace mtg::vlm {

/// One of the three verdict constants of core/tasks/feasibility.h, or "" when the text names none
/// (or several).
std::string parse_verdict(std::string_view text);

struct VoteTally {
  int asked = 0, cast = 0, unreadable = 0, failed = 0;
  double cost_usd = 0.0;
  int cache_hits = 0;
};

/// Votes on every request with `workers` calls in flight. Unreadable answers and failed calls
/// cast no vote (counted in `tally`). @throws mtg::Error when the model stops the agent
/// (authentication, quota): a half-voted task set must not be written.
std::vector<tasks::Vote> cast_votes(ModelClient& client, const PromptSet& prompts,
                                    const std::vector<tasks::VoteRequest>& requests, int workers, VoteTally& tally);

}  // namespace mtg::vlm
