#pragma once
// The model agent: a Policy that keeps one Conversation per episode attempt and answers each
// observation through a ModelClient. Several episodes are answered at once (AgentHost workers).

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

#include "agents/common/policy.h"
#include "agents/vlm/conversation.h"
#include "agents/vlm/model_client.h"
#include "agents/vlm/prompt.h"
#include "agents/vlm/settings.h"

namespace mtg::vlm {

class VlmPolicy : public agents::Policy {
 public:
  VlmPolicy(ModelClient& client, PromptSet prompts, VlmSettings settings);
  void begin(const mtg::episode_start_t& start) override;
  agents::AgentReply reply(const mtg::episode_start_t& start, const mtg::observation_t& observation) override;
  void end(const mtg::episode_start_t& start) override;

 private:
  using Key = std::tuple<std::string, std::int64_t, int>;  // run, episode, attempt
  static Key key_of(const mtg::episode_start_t& start);

  ModelClient& client_;
  PromptSet prompts_;
  VlmSettings settings_;
  std::mutex mutex_;  // guards the map, not the conversations (one thread per episode at a time)
  std::map<Key, std::shared_ptr<Conversation>> conversations_;  // shared: a retry may replace an attempt mid-call
};

}  // namespace mtg::vlm
