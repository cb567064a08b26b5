#include "agents/vlm/vlm_policy.h"

#include "core/util/error.h"

namespace mtg::vlm {

VlmPolicy::VlmPolicy(ModelClient& client, PromptSet prompts, VlmSettings settings)
    : client_(client), prompts_(std::move(prompts)), settings_(std::move(settings)) {}

VlmPolicy::Key VlmPolicy::key_of(const mtg::episode_start_t& start) {
  return {start.header.run_id, start.header.episode_id, start.header.attempt};
}

void VlmPolicy::begin(const mtg::episode_start_t& start) {
  auto conv = std::make_shared<Conversation>(prompts_, settings_, start);
  std::lock_guard lock(mutex_);
  // An older attempt of the same episode is over.
  for (auto it = conversations_.begin(); it != conversations_.end();) {
    const bool older = std::get<0>(it->first) == start.header.run_id &&
                       std::get<1>(it->first) == start.header.episode_id;
    it = older ? conversations_.erase(it) : std::next(it);
  }
  conversations_[key_of(start)] = std::move(conv);
}

void VlmPolicy::end(const mtg::episode_start_t& start) {
  std::lock_guard lock(mutex_);
  conversations_.erase(key_of(start));
}

agents::AgentReply VlmPolicy::reply(const mtg::episode_start_t& start, const mtg::observation_t& observation) {
  std::shared_ptr<Conversation> conv;
  {
    std::lock_guard lock(mutex_);
    const auto it = conversations_.find(key_of(start));
    if (it == conversations_.end()) throw InternalError("observation for an episode that was not begun");
    conv = it->second;
  }
  agents::AgentReply out;
  out.provider = client_.spec().provider_name();
  out.model = client_.spec().model;
  out.prompt_version = prompts_.version;
  std::vector<ChatMessage> messages;
  try {
    messages = conv->ask(observation);
    out.request = conv->last_request();
  } catch (const Error& e) {
    out.error = e.what();
    return out;
  }
  const CallResult r = client_.call(messages);
  out.usage = {r.input_tokens, r.output_tokens, r.images, r.cost_usd, r.latency_ms, r.cache_hit};
  if (!r.ok) {
    out.error = r.error.empty() ? "model call failed" : r.error;
    out.stop_agent = r.stop_agent;
    return out;
  }
  conv->answered(r.text);
  out.raw = r.text;
  return out;
}

}  // namespace mtg::vlm
