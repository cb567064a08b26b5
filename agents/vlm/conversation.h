#pragma once
// One episode's conversation with a model, as the paper prompts it: a system prompt (the robot,
// the keys, the step limit), then per step the observation text, the action space and the
// images, and the model's earlier answers. The history is windowed (history_steps) and only the
// latest steps keep their images (history_images), which bounds tokens on long episodes.

#include <string>
#include <vector>

#include "agents/vlm/chat.h"
#include "agents/vlm/prompt.h"
#include "agents/vlm/settings.h"
#include "core/episode/model_request.h"
#include "mtg/episode_start_t.hpp"
#include "mtg/observation_t.hpp"

namespace mtg::vlm {

class Conversation {
 public:
  Conversation(const PromptSet& prompts, const VlmSettings& settings, const mtg::episode_start_t& start);
  /// Adds `obs` as the next user turn; returns the messages to send for it.
  std::vector<ChatMessage> ask(const mtg::observation_t& obs);
  /// Records the model's answer to the last ask().
  void answered(const std::string& reply);
  /// The last ask()'s request as agent_action_t.request records it (episode::request_record).
  const std::string& last_request() const { return last_request_; }

 private:
  const PromptSet& prompts_;
  const VlmSettings& settings_;
  ChatMessage system_;
  std::vector<ChatMessage> turns_;  // user, assistant, user, assistant, ..., user
  std::vector<episode::SentMessage> sent_;  // the same turns as the record names them
  std::string last_request_;
};

/// One image to send and where it came from.
struct OutgoingImage {
  ImagePart part;
  episode::SentImage sent;
};

/// The observation's images that `settings` sends (by role, in the observation's order), shrunk
/// to image_max_side, as base64. @throws mtg::Error naming the image when it cannot be decoded.
std::vector<OutgoingImage> images_to_send(const mtg::observation_t& obs, const VlmSettings& settings);

/// The user text of one step (the step template filled in).
std::string step_text(const PromptSet& prompts, const VlmSettings& settings, const mtg::observation_t& obs);

}  // namespace mtg::vlm
