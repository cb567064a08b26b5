#pragma once
// The human agent's policy: a desk where the observation waits for a person. reply() puts the
// observation on the desk and blocks until the play page posts one of the offered keys; the page
// reads the desk through the play server (play_server.h). One episode at a time: `mtg play` runs
// with one episode in flight.

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "agents/common/policy.h"
#include "mtg/episode_result_t.hpp"

namespace mtg::agents {

class PlayDesk final : public Policy {
 public:
  AgentReply reply(const mtg::episode_start_t& start, const mtg::observation_t& observation) override;
  void end(const mtg::episode_start_t& start) override;

  /// What the page shows now: {waiting: true, episodes_done, version} between observations, else
  /// {waiting: false, version, episode, attempt, task_text, step, step_limit, text, hint,
  /// actions[{key, description}], images[{role, width, height, url}], done: false, episodes_done};
  /// both with last_verdict ({episode, attempt, retried, success, ip, stage, cause, steps,
  /// detail} or null) and score ({scored, successes, sr, ip}).
  nlohmann::json observation() const;
  /// Answers the observation on the desk with `key`. Returns "" or why the key is refused (no
  /// observation waiting, or a key that is not offered).
  std::string act(const std::string& key);
  /// Waits up to `timeout_ms` for the desk to change from `version` (the next observation, the
  /// episode's end with its verdict); returns observation().
  nlohmann::json wait_change(std::int64_t version, int timeout_ms) const;
  /// The encoded bytes of the current observation's image `index`, with its encoding.
  std::optional<std::pair<std::string, std::vector<std::uint8_t>>> image(int index) const;
  /// Releases a waiting reply() (the process is stopping): it returns an error reply.
  void shutdown();
  /// The judge's verdict on one of the person's attempts: shown after the episode with a running
  /// score. An attempt lost to infrastructure (it is run again) is shown as such, not scored.
  void verdict(const mtg::episode_result_t& result);

 private:
  nlohmann::json observation_locked() const;

  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::optional<mtg::observation_t> current_;
  std::optional<std::string> answer_;
  std::int64_t version_ = 0;  // +1 whenever the desk changes
  // An answer was taken and neither the next observation nor the episode's end has come: the
  // page waits through this instead of showing an empty desk.
  bool between_steps_ = false;
  int episodes_done_ = 0;
  bool stopping_ = false;
  nlohmann::json last_verdict_;  // null until the first verdict
  // The episode that ended and whose verdict has not come yet (-1: none): the desk does not show
  // "episode finished" with the episode before's verdict, it waits for this one's (issue 52).
  std::int64_t awaiting_verdict_ = -1;
  int scored_ = 0, successes_ = 0;
  double ip_sum_ = 0.0;
};

}  // namespace mtg::agents
