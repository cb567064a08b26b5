#include "agents/vlm/voter.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <mutex>
#include <thread>

#include "core/util/error.h"

namespace mtg::vlm {

std::string parse_verdict(std::string_view text) {
  std::string t(text);
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  // The longer phrases contain "feasible", so they are looked for first.
  const bool partial = t.find("partially feasible") != std::string::npos;
  const bool no = t.find("not feasible") != std::string::npos || t.find("infeasible") != std::string::npos;
  std::string rest = t;
  for (const char* phrase : {"partially feasible", "not feasible", "infeasible"}) {
    for (auto pos = rest.find(phrase); pos != std::string::npos; pos = rest.find(phrase)) {
      rest.erase(pos, std::string(phrase).size());
    }
  }
  const bool yes = rest.find("feasible") != std::string::npos;
  if (partial + no + yes != 1) return "";
  return partial ? tasks::kPartiallyFeasible : no ? tasks::kNotFeasible : tasks::kFeasible;
}

std::vector<tasks::Vote> cast_votes(ModelClient& client, const PromptSet& prompts,
                                    const std::vector<tasks::VoteRequest>& requests, int workers, VoteTally& tally) {
  std::vector<std::string> verdicts(requests.size());
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::string stop_reason;
  auto work = [&] {
    for (std::size_t i = next++; i < requests.size(); i = next++) {
      const tasks::VoteRequest& r = requests[i];
      ChatMessage user;
      user.text = render_template(prompts.vote,
                                  {{"task", r.text}, {"scene", r.scene_description},
                                   {"step_limit", std::to_string(r.step_limit)}},
                                  prompts.dir + "/vote.txt");
      const CallResult result = client.call(std::span<const ChatMessage>(&user, 1));
      std::lock_guard lock(mutex);
      tally.cost_usd += result.cost_usd;
      tally.cache_hits += result.cache_hit ? 1 : 0;
      if (result.stop_agent) {
        stop_reason = result.error;
        next = requests.size();
        return;
      }
      if (!result.ok) {
        ++tally.failed;
        continue;
      }
      verdicts[i] = parse_verdict(result.text);
      tally.unreadable += verdicts[i].empty() ? 1 : 0;
    }
  };
  std::vector<std::thread> threads;
  for (int k = 0; k < std::max(1, workers); ++k) threads.emplace_back(work);
  for (auto& t : threads) t.join();
  if (!stop_reason.empty()) throw Error("voter " + client.spec().spec() + " stopped: " + stop_reason);
  tally.asked += static_cast<int>(requests.size());
  std::vector<tasks::Vote> out;
  for (std::size_t i = 0; i < requests.size(); ++i) {
    if (verdicts[i].empty()) continue;
    out.push_back({requests[i].task_id, client.spec().spec(), verdicts[i]});
    ++tally.cast;
  }
  return out;
}

}  // namespace mtg::vlm
