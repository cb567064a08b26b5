// Anthropic Messages (POST <base>/v1/messages). The system prompt is a top-level field; images
// are base64 "image" blocks placed before the text of their message, as Anthropic advises.

#include <nlohmann/json.hpp>

#include "agents/vlm/wire.h"
#include "core/util/error.h"

namespace mtg::vlm::anthropic {

WireRequest build_request(const ModelSpec& spec, const GenerationParams& params,
                          std::span<const ChatMessage> messages) {
  const std::string system = system_text(messages);
  nlohmann::json msgs = nlohmann::json::array();
  for (const ChatMessage& m : messages) {
    if (m.role == ChatMessage::Role::kSystem) continue;
    nlohmann::json blocks = nlohmann::json::array();
    for (const ImagePart& img : m.images) {
      blocks.push_back(
          {{"type", "image"}, {"source", {{"type", "base64"}, {"media_type", img.mime}, {"data", img.base64}}}});
    }
    blocks.push_back({{"type", "text"}, {"text", m.text}});
    msgs.push_back({{"role", m.role == ChatMessage::Role::kAssistant ? "assistant" : "user"}, {"content", blocks}});
  }
  nlohmann::json body = {{"model", spec.model},
                         {"max_tokens", params.max_output_tokens},
                         {"temperature", params.temperature},
                         {"messages", msgs}};
  if (!system.empty()) body["system"] = system;
  return {spec.base_url + "/v1/messages", body.dump()};
}

ModelAnswer parse_answer(const std::string& body) {
  const nlohmann::json j = nlohmann::json::parse(body);
  const nlohmann::json& content = j.at("content");
  if (!content.is_array()) throw Error("malformed response: content is not a list of blocks");
  ModelAnswer a;
  for (const auto& block : content) {
    if (block.is_object() && block.value("type", "") == "text") a.text += block.value("text", "");
  }
  if (j.contains("usage") && j["usage"].is_object()) {
    a.input_tokens = j["usage"].value("input_tokens", 0);
    a.output_tokens = j["usage"].value("output_tokens", 0);
  }
  return a;
}

}  // namespace mtg::vlm::anthropic
